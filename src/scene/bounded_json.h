#pragma once
// JSON read before any recursive parser sees it: nlohmann's parser is iterative, so a
// file nesting 15,000 arrays cannot overflow the stack here; the depth and size are then bounded
// so that tinygltf's recursive value parser, and every recursive walk of ours (dump, copies), stay
// shallow. Numbers keep their JSON form (64-bit integers, unsigned, or double): 4294967296 reads
// as 4294967296, and nulls and empty members stay visible.
#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/expected.h"

namespace daisy {

// Real glTF files nest about 8 levels (materials[i].extensions.X.fluorescence.matrix.values[o][i]
// is 8); 64 leaves room for any extras while keeping recursion a few KiB deep.
inline constexpr int kMaxJsonDepth = 64;
inline constexpr std::size_t kMaxJsonBytes = std::size_t(512) << 20;

// Parses `text`; errors (without the file name, which the caller adds) read "invalid JSON at
// line 3, column 7: ...", "JSON nests deeper than 64 levels at byte 812" or "the JSON text is
// 600 MiB, over the 512 MiB limit".
// With Keys::Unique, an object that names a key twice is refused ("floor: the key \"reflectance\"
// appears twice in this object"): nlohmann keeps the last silently, and in a file a person edits
// by hand (--materials) which one was meant is a guess. glTF files keep nlohmann's rule, as
// tinygltf and other readers do.
enum class JsonKeys { LastWins, Unique };
Expected<nlohmann::json> parseBoundedJson(std::string_view text, int maxDepth = kMaxJsonDepth,
                                          JsonKeys keys = JsonKeys::LastWins);

// object[key] when `object` is an object holding `key`, else null.
const nlohmann::json* jsonMember(const nlohmann::json& object, const char* key);

// "string \"abc\"", "null", "object {...}": a value's type and a short excerpt, for messages.
std::string describeJson(const nlohmann::json& value);

}  // namespace daisy
