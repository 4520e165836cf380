#include "scene/gltf_meshopt.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <vector>

#include "core/strings.h"

namespace daisy {
namespace {

constexpr std::array<const char*, 2> kNames = {"EXT_meshopt_compression",
                                               "KHR_meshopt_compression"};

const nlohmann::json* compression(const nlohmann::json& object) {
    if (!object.is_object()) return nullptr;
    const auto extensions = object.find("extensions");
    if (extensions == object.end() || !extensions->is_object()) return nullptr;
    for (const char* name : kNames) {
        const auto it = extensions->find(name);
        if (it != extensions->end()) return &*it;
    }
    return nullptr;
}

constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string base64Encode(std::string_view bytes) {
    std::string text;
    text.reserve((bytes.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t group = uint32_t(static_cast<unsigned char>(bytes[i])) << 16;
        if (i + 1 < bytes.size()) group |= uint32_t(static_cast<unsigned char>(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) group |= uint32_t(static_cast<unsigned char>(bytes[i + 2]));
        text += kAlphabet[(group >> 18) & 63];
        text += kAlphabet[(group >> 12) & 63];
        text += i + 1 < bytes.size() ? kAlphabet[(group >> 6) & 63] : '=';
        text += i + 2 < bytes.size() ? kAlphabet[group & 63] : '=';
    }
    return text;
}

Expected<std::string> base64Decode(std::string_view text) {
    std::array<int, 256> value;
    value.fill(-1);
    for (int k = 0; k < 64; ++k)
        value[static_cast<unsigned char>(kAlphabet[k])] = k;
    std::string bytes;
    uint32_t group = 0;
    int bits = 0;
    for (char c : text) {
        if (c == '=') break;
        const int v = value[static_cast<unsigned char>(c)];
        if (v < 0) return Error{"a data: uri that is not base64"};
        group = (group << 6) | uint32_t(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            bytes += static_cast<char>((group >> bits) & 0xff);
        }
    }
    return bytes;
}

}  // namespace

std::string gltfDataUri(std::string_view bytes) {
    return "data:application/octet-stream;base64," + base64Encode(bytes);
}

void inlineBuffersAndDropExtensions(nlohmann::json& root, std::string_view glbBin,
                                    std::initializer_list<const char*> names) {
    nlohmann::json& buffers = root["buffers"];
    for (std::size_t b = 0; b < buffers.size(); ++b) {
        nlohmann::json& buffer = buffers[b];
        if (buffer.contains("uri")) continue;
        const std::string bytes =
            b == 0 && !glbBin.empty() ? std::string(glbBin) : std::string(4, '\0');
        buffer["uri"] = gltfDataUri(bytes);
        buffer["byteLength"] = bytes.size();
    }
    for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
        if (!root.contains(list) || !root[list].is_array()) continue;
        nlohmann::json kept = nlohmann::json::array();
        for (const nlohmann::json& entry : root[list]) {
            if (std::none_of(names.begin(), names.end(),
                             [&](const char* name) { return entry == name; }))
                kept.push_back(entry);
        }
        root[list] = std::move(kept);
    }
}

Expected<std::string> gltfBufferBytes(const nlohmann::json& buffer, std::size_t index,
                                      const std::string& folder, std::string_view glbBin) {
    const auto uri = buffer.find("uri");
    if (uri == buffer.end()) {
        if (index == 0) return std::string(glbBin);
        return Error{concat("buffers[", index, "] has no data")};
    }
    if (!uri->is_string()) return Error{concat("buffers[", index, "].uri: expected a string")};
    const std::string text = uri->get<std::string>();
    if (text.rfind("data:", 0) == 0) {
        const std::size_t comma = text.find(',');
        if (comma == std::string::npos) return Error{concat("buffers[", index, "].uri: no data")};
        return base64Decode(std::string_view(text).substr(comma + 1));
    }
    const std::filesystem::path path = std::filesystem::path(folder) / text;
    std::ifstream file(path, std::ios::binary);
    if (!file) return Error{concat("buffers[", index, "].uri: cannot read '", text, "'")};
    return std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

namespace {

uint64_t integer(const nlohmann::json& object, const char* key, uint64_t fallback) {
    const auto it = object.find(key);
    if (it == object.end() || !it->is_number_unsigned()) return fallback;
    return it->get<uint64_t>();
}

}  // namespace

bool usesMeshoptCompression(const nlohmann::json& root) {
    const auto views = root.find("bufferViews");
    if (views == root.end() || !views->is_array()) return false;
    return std::any_of(views->begin(), views->end(),
                       [](const nlohmann::json& view) { return compression(view) != nullptr; });
}

Expected<void> decodeMeshoptViews(nlohmann::json& root, const std::string& folder,
                                  std::string_view glbBin, LoadBudget& budget) {
    nlohmann::json& buffers = root["buffers"];
    if (!buffers.is_array()) return Error{"buffers: expected an array"};
    std::vector<std::string> sources(buffers.size());
    std::vector<char> loaded(buffers.size(), 0);
    std::string decoded;
    nlohmann::json& views = root["bufferViews"];
    const std::size_t newBuffer = buffers.size();
    for (std::size_t v = 0; v < views.size(); ++v) {
        nlohmann::json& view = views[v];
        const nlohmann::json* ext = compression(view);
        if (ext == nullptr) continue;
        const std::string where = concat("bufferViews[", v, "].extensions.EXT_meshopt_compression");
        const uint64_t buffer = integer(*ext, "buffer", UINT64_MAX);
        const uint64_t offset = integer(*ext, "byteOffset", 0);
        const uint64_t length = integer(*ext, "byteLength", UINT64_MAX);
        const uint64_t stride = integer(*ext, "byteStride", 0);
        const uint64_t count = integer(*ext, "count", UINT64_MAX);
        if (buffer >= buffers.size() || length == UINT64_MAX || count == UINT64_MAX ||
            stride == 0 || stride > 256) {
            return Error{where +
                         ": buffer, byteLength, byteStride (1..256) and count are required"};
        }
        if (!loaded[buffer]) {
            auto bytes = gltfBufferBytes(buffers[buffer], buffer, folder, glbBin);
            if (!bytes) return withContext(bytes.error(), where);
            sources[buffer] = std::move(*bytes);
            loaded[buffer] = 1;
        }
        const std::string& source = sources[buffer];
        if (offset > source.size() || length > source.size() - offset) {
            return Error{concat(where, ": bytes [", offset, ", ", offset + length,
                                ") exceed buffers[", buffer, "] (", source.size(), " bytes)")};
        }
        const uint64_t size = count * stride;
        if (count != 0 && size / count != stride)
            return Error{where + ": count x byteStride overflows"};
        if (auto charged = budget.charge(size * 2, concat(where, ": ", count, " elements"));
            !charged) {
            return charged.error();
        }
        decoded.resize((decoded.size() + 3) / 4 * 4, '\0');
        const std::size_t at = decoded.size();
        decoded.resize(at + size);
        void* out = decoded.data() + at;
        const auto* in = reinterpret_cast<const unsigned char*>(source.data() + offset);
        const std::string mode = ext->value("mode", std::string());
        const std::string filter = ext->value("filter", std::string("NONE"));
        // libmeshoptimizer asserts its preconditions (Debian builds it with assertions on): every
        // count, stride and filter is checked here first (EXT_meshopt_compression's rules).
        if (mode == "ATTRIBUTES" && stride % 4 != 0) {
            return Error{concat(where, ".byteStride: ", stride,
                                " is not a multiple of 4, as ATTRIBUTES requires")};
        }
        if (mode == "TRIANGLES" && count % 3 != 0) {
            return Error{
                concat(where, ".count: ", count, " is not a multiple of 3, as TRIANGLES requires")};
        }
        if (filter != "NONE" &&
            (mode != "ATTRIBUTES" || (filter == "OCTAHEDRAL" && stride != 4 && stride != 8) ||
             (filter == "QUATERNION" && stride != 8))) {
            return Error{concat(where, ".filter: \"", filter, "\" does not apply to mode \"", mode,
                                "\" with byteStride ", stride)};
        }
        int status = -1;
        if (mode == "ATTRIBUTES") {
            status = meshopt_decodeVertexBuffer(out, count, stride, in, length);
        } else if (mode == "TRIANGLES" && (stride == 2 || stride == 4)) {
            status = meshopt_decodeIndexBuffer(out, count, stride, in, length);
        } else if (mode == "INDICES" && (stride == 2 || stride == 4)) {
            status = meshopt_decodeIndexSequence(out, count, stride, in, length);
        } else {
            return Error{concat(where, ".mode: \"", mode, "\" with byteStride ", stride,
                                " is not ATTRIBUTES, TRIANGLES or INDICES (2 or 4 bytes)")};
        }
        if (status != 0) return Error{where + ": the compressed data cannot be decoded"};
        if (filter == "OCTAHEDRAL") {
            meshopt_decodeFilterOct(out, count, stride);
        } else if (filter == "QUATERNION") {
            meshopt_decodeFilterQuat(out, count, stride);
        } else if (filter == "EXPONENTIAL") {
            meshopt_decodeFilterExp(out, count, stride);
        } else if (filter != "NONE") {
            return Error{concat(where, ".filter: \"", filter, "\" is not a known filter")};
        }
        view["buffer"] = newBuffer;
        view["byteOffset"] = at;
        view["byteLength"] = size;
        view["extensions"].erase("EXT_meshopt_compression");
        view["extensions"].erase("KHR_meshopt_compression");
        if (view["extensions"].empty()) view.erase("extensions");
    }
    // Fallback buffers carry the extension too; they become data: uris below.
    for (nlohmann::json& buffer : buffers) {
        if (!buffer.contains("uri") && buffer.contains("extensions")) buffer.erase("extensions");
    }
    buffers.push_back({{"byteLength", decoded.size()}, {"uri", gltfDataUri(decoded)}});
    inlineBuffersAndDropExtensions(root, glbBin, {kNames[0], kNames[1]});
    return {};
}

}  // namespace daisy
