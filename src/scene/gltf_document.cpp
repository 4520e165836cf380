#include "scene/gltf_document.h"

#include <cmath>
#include <cstring>
#include <filesystem>

#include "core/strings.h"
#include "scene/bounded_json.h"

namespace daisy {
namespace {

constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr uint32_t kChunkBin = 0x004E4942;  // "BIN\0"

uint32_t readU32(std::string_view bytes, std::size_t offset) {
    uint32_t value = 0;
    std::memcpy(&value, bytes.data() + offset, sizeof value);  // GLB is little-endian
    return value;
}

std::string hex(uint32_t value) {
    std::ostringstream out;
    out << "0x" << std::hex << std::uppercase << value;
    return out.str();
}

// Reads the chunk header at `offset`; `name` is "chunk 0 (JSON)" or "chunk 1 (BIN)".
Expected<std::string_view> readChunk(std::string_view bytes, std::size_t offset, uint32_t type,
                                     const char* name) {
    if (bytes.size() - offset < 8) {
        return Error{concat("GLB ", name, ": its 8-byte header at byte ", offset,
                            " is cut off (the file ends at byte ", bytes.size(), ")")};
    }
    const uint32_t length = readU32(bytes, offset);
    const uint32_t found = readU32(bytes, offset + 4);
    if (found != type) {
        return Error{concat("GLB ", name, ": chunkType ", hex(found), " at byte ", offset + 4,
                            ", expected ", hex(type))};
    }
    if (length > bytes.size() - offset - 8) {
        return Error{concat("GLB ", name, ": chunkLength ", length, " at byte ", offset,
                            " runs past the end of the file (", bytes.size() - offset - 8,
                            " bytes follow the chunk header)")};
    }
    return bytes.substr(offset + 8, length);
}

// "2.1" -> {2, 1}; false unless it is <digits>.<digits> (glTF 2.0 section 5.2 pattern).
bool parseVersion(const std::string& text, long& major, long& minor) {
    const std::size_t dot = text.find('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 == text.size()) return false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (i != dot && !(text[i] >= '0' && text[i] <= '9')) return false;
    }
    if (dot > 6 || text.size() - dot > 7) return false;
    major = std::stol(text.substr(0, dot));
    minor = std::stol(text.substr(dot + 1));
    return true;
}

// A relative uri's file (percent-escapes decoded, as glTF 2.0 section 3.1 allows).
std::filesystem::path uriFile(const std::string& folder, const std::string& uri) {
    std::string decoded;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit((unsigned char)uri[i + 1]) &&
            std::isxdigit((unsigned char)uri[i + 2])) {
            decoded += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            decoded += uri[i];
        }
    }
    return std::filesystem::path(folder.empty() ? "." : folder) / decoded;
}

// Why `uri` cannot name the file of `where`, or "" when it can (or is a data: uri).
// Why a data: uri cannot hold the bytes tinygltf would decode from it, or "" when it can: glTF
// embeds data as "data:<mime>;base64,<base64>" (RFC 2397).
std::string dataUriProblem(const std::string& uri) {
    const std::size_t comma = uri.find(',');
    if (comma == std::string::npos || uri.substr(0, comma).find(";base64") == std::string::npos) {
        return "the data: uri is not base64 (\"data:<type>;base64,...\" expected)";
    }
    const std::string_view payload = std::string_view(uri).substr(comma + 1);
    if (payload.empty()) return "the data: uri holds no data";
    std::size_t padding = 0;
    for (std::size_t k = 0; k < payload.size(); ++k) {
        const char c = payload[k];
        const bool digit = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') ||
            (c >= '0' && c <= '9') || c == '+' || c == '/';
        if (c == '=' && padding < 2) {
            ++padding;
            continue;
        }
        if (!digit || padding > 0) {
            return concat("the data: uri is not base64: character ", comma + 1 + k + 1, " is ", "'",
                          printable(std::string_view(&c, 1)), "'");
        }
    }
    return {};
}

std::string uriProblem(const std::string& folder, const std::string& uri, uint64_t& fileBytes) {
    fileBytes = 0;
    if (uri.starts_with("data:")) return dataUriProblem(uri);
    std::error_code ec;
    const std::filesystem::path file = uriFile(folder, uri);
    const auto status = std::filesystem::status(file, ec);
    if (!std::filesystem::exists(status))
        return concat("'", uri, "' does not exist (", file.string(), ")");
    if (std::filesystem::is_directory(status)) return concat("'", uri, "' is a folder, not a file");
    if (!std::filesystem::is_regular_file(status))
        return concat("'", uri, "' is not a regular file");
    fileBytes = std::filesystem::file_size(file, ec);
    return {};
}

}  // namespace

Expected<GlbChunks> splitGlb(std::string_view bytes) {
    if (bytes.size() < 12) {
        return Error{concat("GLB header: the file has ", bytes.size(),
                            " bytes, fewer than the 12-byte header")};
    }
    if (readU32(bytes, 0) != kGlbMagic) {
        return Error{concat("GLB header: magic ", hex(readU32(bytes, 0)), ", expected ",
                            hex(kGlbMagic), " (\"glTF\")")};
    }
    if (const uint32_t version = readU32(bytes, 4); version != 2) {
        return Error{concat("GLB header: version ", version, ", expected 2")};
    }
    if (const uint32_t length = readU32(bytes, 8); length != bytes.size()) {
        return Error{concat("GLB header: length ", length, ", but the file has ", bytes.size(),
                            " bytes", length > bytes.size() ? " (truncated?)" : "")};
    }
    GlbChunks chunks;
    auto json = readChunk(bytes, 12, kChunkJson, "chunk 0 (JSON)");
    if (!json) return json.error();
    chunks.json = *json;
    std::size_t next = 12 + 8 + chunks.json.size();
    next += (4 - next % 4) % 4;  // chunks start 4-byte aligned
    if (next < bytes.size()) {
        auto bin = readChunk(bytes, next, kChunkBin, "chunk 1 (BIN)");
        if (!bin) return bin.error();
        chunks.bin = *bin;
        chunks.hasBin = true;
    }
    return chunks;
}

Expected<void> checkGltfAsset(const nlohmann::json& root) {
    if (!root.is_object())
        return Error{"the top level is " + describeJson(root) + ", expected an object"};
    const auto asset = root.find("asset");
    if (asset == root.end() || !asset->is_object()) {
        return Error{"asset: missing or not an object; glTF 2.0 requires asset.version \"2.0\""};
    }
    const auto version = asset->find("version");
    long major = 0, minor = 0;
    if (version == asset->end() || !version->is_string() ||
        !parseVersion(version->get<std::string>(), major, minor)) {
        return Error{
            concat("asset.version: ",
                   version == asset->end() ? std::string("missing") : describeJson(*version),
                   ", expected a string \"2.0\"")};
    }
    if (major != 2) {
        return Error{concat("asset.version: \"", version->get<std::string>(),
                            "\" is not glTF 2.x; daisy reads glTF 2.0")};
    }
    if (const auto minVersion = asset->find("minVersion"); minVersion != asset->end()) {
        long minMajor = 0, minMinor = 0;
        if (!minVersion->is_string() ||
            !parseVersion(minVersion->get<std::string>(), minMajor, minMinor)) {
            return Error{"asset.minVersion: " + describeJson(*minVersion) +
                         ", expected a string such as \"2.0\""};
        }
        if (minMajor != 2 || minMinor > 0) {
            return Error{concat("asset.minVersion: \"", minVersion->get<std::string>(),
                                "\" is newer than glTF 2.0, which is what daisy reads")};
        }
    }
    return {};
}

Expected<void> checkGltfResources(const nlohmann::json& root, const std::string& folder,
                                  uint64_t binBytes, bool isGlb, LoadBudget& budget) {
    if (const auto buffers = root.find("buffers"); buffers != root.end()) {
        if (!buffers->is_array())
            return Error{"buffers: " + describeJson(*buffers) + ", expected an array"};
        for (std::size_t k = 0; k < buffers->size(); ++k) {
            const nlohmann::json& buffer = (*buffers)[k];
            const std::string where = concat("buffers[", k, "]");
            if (!buffer.is_object())
                return Error{where + ": " + describeJson(buffer) + ", expected an object"};
            const auto length = buffer.find("byteLength");
            const bool integral = length != buffer.end() &&
                (length->is_number_unsigned() ||
                 (length->is_number_float() && length->get<double>() >= 0 &&
                  length->get<double>() <= 9e15 &&
                  length->get<double>() == std::floor(length->get<double>())));
            if (!integral) {
                return Error{
                    concat(where, ".byteLength: ",
                           length == buffer.end() ? std::string("missing") : describeJson(*length),
                           ", expected an integer >= 1")};
            }
            const uint64_t byteLength = length->is_number_unsigned()
                ? length->get<uint64_t>()
                : static_cast<uint64_t>(length->get<double>());
            const auto uri = buffer.find("uri");
            uint64_t available = 0;
            if (uri == buffer.end()) {
                if (!(isGlb && k == 0)) {
                    return Error{where +
                                 ".uri: missing; only the first buffer of a .glb may "
                                 "omit it (the BIN chunk)"};
                }
                available = binBytes;
            } else if (!uri->is_string()) {
                return Error{where + ".uri: " + describeJson(*uri) + ", expected a string"};
            } else {
                const std::string text = uri->get<std::string>();
                if (const std::string problem = uriProblem(folder, text, available);
                    !problem.empty()) {
                    return Error{where + ".uri: " + problem};
                }
                if (text.starts_with("data:")) available = text.size();  // base64 is longer
            }
            if (available < byteLength) {
                return Error{concat(where, ".byteLength: ", byteLength,
                                    " bytes, but its data has only ", available)};
            }
            auto charged = budget.charge(byteLength, where);
            if (!charged) return charged;
        }
    }
    if (const auto images = root.find("images"); images != root.end() && images->is_array()) {
        for (std::size_t k = 0; k < images->size(); ++k) {
            const nlohmann::json& image = (*images)[k];
            if (!image.is_object()) continue;
            const auto uri = image.find("uri");
            if (uri == image.end() || !uri->is_string()) continue;
            uint64_t bytes = 0;
            const std::string problem = uriProblem(folder, uri->get<std::string>(), bytes);
            // A missing image is tinygltf's to report; only what would crash it is refused here.
            if (!problem.empty() && problem.find("does not exist") == std::string::npos) {
                return Error{concat("images[", k, "].uri: ", problem)};
            }
        }
    }
    return {};
}

}  // namespace daisy
