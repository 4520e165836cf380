#pragma once
// Builds small glTF documents for tests (tests/scene): one binary buffer, tightly packed views,
// written as .gltf (embedded or side .bin) or .glb.
#include <array>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_util.h"

namespace daisy::test {

using nlohmann::json;
using Float3 = std::array<float, 3>;

inline std::string base64(const std::string& bytes) {
    static constexpr char kAlphabet[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string text;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t group = static_cast<uint32_t>(static_cast<unsigned char>(bytes[i])) << 16;
        if (i + 1 < bytes.size()) group |= static_cast<unsigned char>(bytes[i + 1]) << 8;
        if (i + 2 < bytes.size()) group |= static_cast<unsigned char>(bytes[i + 2]);
        text += kAlphabet[(group >> 18) & 63];
        text += kAlphabet[(group >> 12) & 63];
        text += i + 1 < bytes.size() ? kAlphabet[(group >> 6) & 63] : '=';
        text += i + 2 < bytes.size() ? kAlphabet[group & 63] : '=';
    }
    return text;
}

inline void appendUint32(std::string& out, uint32_t value) {
    out.append(reinterpret_cast<const char*>(&value), 4);  // little-endian host
}

// Builds a glTF document with one binary buffer; views are tightly packed, 4-byte aligned.
class GltfBuilder {
public:
    json doc = {{"asset", {{"version", "2.0"}}},
                {"bufferViews", json::array()},
                {"accessors", json::array()},
                {"meshes", json::array()},
                {"nodes", json::array()}};
    std::string bin;

    int addView(const void* data, std::size_t size) {
        bin.resize((bin.size() + 3) / 4 * 4, '\0');
        doc["bufferViews"].push_back(
            {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", size}});
        bin.append(static_cast<const char*>(data), size);
        return static_cast<int>(doc["bufferViews"].size()) - 1;
    }
    int addAccessor(int view, int componentType, std::size_t count, const char* type) {
        doc["accessors"].push_back({{"bufferView", view},
                                    {"componentType", componentType},
                                    {"count", count},
                                    {"type", type}});
        return static_cast<int>(doc["accessors"].size()) - 1;
    }
    int addVec2(const std::vector<std::array<float, 2>>& values) {
        const int view = addView(values.data(), values.size() * sizeof(values[0]));
        return addAccessor(view, 5126, values.size(), "VEC2");
    }
    int addPositions(const std::vector<Float3>& positions) {
        const int view = addView(positions.data(), positions.size() * sizeof(Float3));
        return addAccessor(view, 5126, positions.size(), "VEC3");
    }
    template <typename T>
    int addIndices(const std::vector<T>& indices) {
        const int view = addView(indices.data(), indices.size() * sizeof(T));
        const int componentType = sizeof(T) == 1 ? 5121 : sizeof(T) == 2 ? 5123 : 5125;
        return addAccessor(view, componentType, indices.size(), "SCALAR");
    }
    int addMesh(json primitives) {
        doc["meshes"].push_back({{"primitives", std::move(primitives)}});
        return static_cast<int>(doc["meshes"].size()) - 1;
    }
    int addNode(json node) {
        doc["nodes"].push_back(std::move(node));
        return static_cast<int>(doc["nodes"].size()) - 1;
    }
    void setScene(const std::vector<int>& roots) {
        doc["scenes"] = json::array({{{"nodes", roots}}});
        doc["scene"] = 0;
    }
    // One mesh with one primitive over `positions`, on one root node with `node`'s members.
    void addSingleTriangleScene(const std::vector<Float3>& positions, json node = json::object()) {
        const int accessor = addPositions(positions);
        node["mesh"] = addMesh({{{"attributes", {{"POSITION", accessor}}}}});
        setScene({addNode(node)});
    }

    // The buffer embedded as a base64 data URI.
    std::string writeGltf(const std::filesystem::path& dir, const std::string& name) const {
        json file = doc;
        if (!bin.empty()) {
            file["buffers"] = {{{"byteLength", bin.size()},
                                {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
        }
        return writeFile(dir, name, file.dump());
    }
    // The buffer in a side file `binName` next to the .gltf.
    std::string writeGltfWithBin(const std::filesystem::path& dir, const std::string& name,
                                 const std::string& binName) const {
        json file = doc;
        file["buffers"] = {{{"byteLength", bin.size()}, {"uri", binName}}};
        writeFile(dir, binName, bin);
        return writeFile(dir, name, file.dump());
    }
    // The binary container of glTF 2.0 section 4.4: header, JSON chunk, BIN chunk.
    std::string glbBytes() const {
        json file = doc;
        file["buffers"] = {{{"byteLength", bin.size()}}};
        std::string text = file.dump();
        text.resize((text.size() + 3) / 4 * 4, ' ');
        std::string data = bin;
        data.resize((data.size() + 3) / 4 * 4, '\0');
        std::string out = "glTF";
        appendUint32(out, 2);
        appendUint32(out, static_cast<uint32_t>(12 + 8 + text.size() + 8 + data.size()));
        appendUint32(out, static_cast<uint32_t>(text.size()));
        appendUint32(out, 0x4E4F534A);  // "JSON"
        out += text;
        appendUint32(out, static_cast<uint32_t>(data.size()));
        appendUint32(out, 0x004E4942);  // "BIN\0"
        return out + data;
    }
};

}  // namespace daisy::test
