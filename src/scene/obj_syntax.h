#pragma once
// The numbers of OBJ and MTL statements, checked with their line before tinyobjloader reads
// them: tinyobjloader reads "nan", "hello" or "1e999" as 0 or infinity without a
// word. Internal to scene/ (obj_loader.cpp). Errors read
// "<file>:<line>: v: 'hello' is not a number (expected x y z [w])".
#include <string>
#include <string_view>
#include <vector>

#include "core/expected.h"

namespace daisy {

// Checks v / vn / vt coordinates (finite numbers, the right count) and f / l / p corner
// references (non-zero integers, v/vt/vn form). `file` prefixes messages.
Expected<void> checkObjNumbers(std::string_view text, const std::string& file);

// Checks the colour and scalar statements daisy reads or tinyobjloader parses as numbers
// (Ka Kd Ks Ke Tf: 1 or 3 numbers, or "spectral"/"xyz" forms left alone; Ns Ni d Tr illum: one).
Expected<void> checkMtlNumbers(std::string_view text, const std::string& file);

// The file names of the OBJ's mtllib statements, in order.
std::vector<std::string> objMaterialLibraries(std::string_view text);

}  // namespace daisy
