#include "scene/gltf_draco.h"

#include <draco/compression/decode.h>
#include <draco/core/decoder_buffer.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "core/strings.h"
#include "scene/gltf_meshopt.h"

namespace daisy {
namespace {

constexpr const char* kName = "KHR_draco_mesh_compression";
constexpr int kFloat = 5126;
constexpr int kUnsignedInt = 5125;

const nlohmann::json* dracoExtension(const nlohmann::json& primitive) {
    if (!primitive.is_object()) return nullptr;
    const auto extensions = primitive.find("extensions");
    if (extensions == primitive.end() || !extensions->is_object()) return nullptr;
    const auto it = extensions->find(kName);
    return it == extensions->end() ? nullptr : &*it;
}

// The non-negative integer at object[key], or -1.
int64_t index(const nlohmann::json& object, const char* key) {
    if (!object.is_object()) return -1;
    const auto it = object.find(key);
    if (it == object.end() || !it->is_number_unsigned()) return -1;
    const uint64_t value = it->get<uint64_t>();
    return value > uint64_t(INT32_MAX) ? -1 : int64_t(value);
}

int componentsOf(const std::string& type) {
    if (type == "SCALAR") return 1;
    if (type == "VEC2") return 2;
    if (type == "VEC3") return 3;
    if (type == "VEC4") return 4;
    return 0;
}

// Appends `bytes` to `decoded` (4-byte aligned) as a new bufferView of `buffer`; its index.
std::size_t addView(nlohmann::json& views, std::string& decoded, std::size_t buffer,
                    const void* bytes, std::size_t size) {
    decoded.resize((decoded.size() + 3) / 4 * 4, '\0');
    const std::size_t at = decoded.size();
    decoded.append(static_cast<const char*>(bytes), size);
    views.push_back({{"buffer", buffer}, {"byteOffset", at}, {"byteLength", size}});
    return views.size() - 1;
}

void pointAccessor(nlohmann::json& accessor, std::size_t view, int componentType) {
    accessor["bufferView"] = view;
    accessor["byteOffset"] = 0;
    accessor["componentType"] = componentType;
    accessor.erase("normalized");
    accessor.erase("sparse");
}

struct Sources {
    const std::string& folder;
    std::string_view glbBin;
    std::vector<std::string> bytes;
    std::vector<char> loaded;
};

// The compressed bytes of bufferViews[view].
Expected<std::string_view> viewBytes(const nlohmann::json& root, int64_t view, Sources& sources) {
    const nlohmann::json& views = root["bufferViews"];
    if (view < 0 || !views.is_array() || std::size_t(view) >= views.size())
        return Error{concat("bufferView ", view, " does not exist")};
    const nlohmann::json& v = views[std::size_t(view)];
    const int64_t buffer = index(v, "buffer");
    const int64_t length = index(v, "byteLength");
    const int64_t offset = v.contains("byteOffset") ? index(v, "byteOffset") : 0;
    const nlohmann::json& buffers = root["buffers"];
    if (buffer < 0 || std::size_t(buffer) >= buffers.size() || length < 0 || offset < 0)
        return Error{concat("bufferViews[", view, "]: buffer, byteOffset and byteLength")};
    const std::size_t b = std::size_t(buffer);
    if (!sources.loaded[b]) {
        auto bytes = gltfBufferBytes(buffers[b], b, sources.folder, sources.glbBin);
        if (!bytes) return withContext(bytes.error(), concat("bufferViews[", view, "]"));
        sources.bytes[b] = std::move(*bytes);
        sources.loaded[b] = 1;
    }
    const std::string& data = sources.bytes[b];
    if (uint64_t(offset) > data.size() || uint64_t(length) > data.size() - uint64_t(offset)) {
        return Error{concat("bufferViews[", view, "]: bytes [", offset, ", ", offset + length,
                            ") exceed buffers[", b, "] (", data.size(), " bytes)")};
    }
    return std::string_view(data).substr(std::size_t(offset), std::size_t(length));
}

// accessors[id], checked to exist.
Expected<nlohmann::json*> accessorOf(nlohmann::json& root, int64_t id, const std::string& what) {
    nlohmann::json& accessors = root["accessors"];
    if (id < 0 || !accessors.is_array() || std::size_t(id) >= accessors.size())
        return Error{concat(what, ": accessor ", id, " does not exist")};
    nlohmann::json& accessor = accessors[std::size_t(id)];
    if (!accessor.is_object()) return Error{concat(what, ": accessors[", id, "] is not an object")};
    return &accessor;
}

Expected<void> decodePrimitive(nlohmann::json& root, nlohmann::json& primitive,
                               const std::string& where, Sources& sources, std::string& decoded,
                               std::size_t newBuffer, LoadBudget& budget) {
    const nlohmann::json& ext = *dracoExtension(primitive);
    const int64_t view = index(ext, "bufferView");
    if (view < 0) return Error{where + ": bufferView is required"};
    const auto attributes = ext.find("attributes");
    if (attributes == ext.end() || !attributes->is_object())
        return Error{where + ": attributes is required (an object of attribute ids)"};
    if (primitive.contains("mode") && primitive["mode"] != 4)
        return Error{where + ": only triangle primitives (mode 4) can be Draco-compressed"};
    auto bytes = viewBytes(root, view, sources);
    if (!bytes) return withContext(bytes.error(), where);

    draco::DecoderBuffer input;
    input.Init(bytes->data(), bytes->size());
    draco::Decoder decoder;
    auto result = decoder.DecodeMeshFromBuffer(&input);
    if (!result.ok()) {
        return Error{concat(where, ": the compressed data in bufferViews[", view,
                            "] cannot be decoded (draco: ", result.status().error_msg_string(),
                            ")")};
    }
    const std::unique_ptr<draco::Mesh> mesh = std::move(result).value();
    if (!mesh) return Error{concat(where, ": bufferViews[", view, "] decodes to no mesh")};
    const uint64_t faces = mesh->num_faces();
    const uint64_t points = mesh->num_points();

    nlohmann::json& views = root["bufferViews"];
    // Indices: three per decoded face, as uint32.
    if (primitive.contains("indices")) {
        const int64_t id = index(primitive, "indices");
        auto accessor = accessorOf(root, id, where + ": indices");
        if (!accessor) return accessor.error();
        const int64_t count = index(**accessor, "count");
        if (count < 0 || uint64_t(count) != faces * 3) {
            return Error{concat(where, ": indices accessor ", id, " has count ", count,
                                " but the decoded mesh has ", faces, " triangles (", faces * 3,
                                " indices)")};
        }
        if (auto charged = budget.charge(faces * 12, concat(where, ": ", faces, " triangles"));
            !charged) {
            return charged.error();
        }
        std::vector<uint32_t> indices;
        indices.reserve(faces * 3);
        for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
            for (const draco::PointIndex& p : mesh->face(f))
                indices.push_back(p.value());
        }
        pointAccessor(
            **accessor,
            addView(views, decoded, newBuffer, indices.data(), indices.size() * sizeof(uint32_t)),
            kUnsignedInt);
    } else if (faces * 3 != points) {
        return Error{concat(where, ": no indices, but the decoded mesh has ", faces,
                            " triangles over ", points, " points")};
    }

    // Attributes: the extension's id for each name, its values per point as float.
    nlohmann::json& primitiveAttributes = primitive["attributes"];
    for (const auto& [name, idValue] : attributes->items()) {
        const std::string what = concat(where, ": attribute ", name);
        if (!idValue.is_number_unsigned() || idValue.get<uint64_t>() > uint64_t(INT32_MAX))
            return Error{what + ": the Draco attribute id is not a non-negative integer"};
        const int64_t accessorId = index(primitiveAttributes, name.c_str());
        if (accessorId < 0)
            return Error{what + ": the primitive's attributes do not name its accessor"};
        auto accessor = accessorOf(root, accessorId, what);
        if (!accessor) return accessor.error();
        const uint32_t uniqueId = idValue.get<uint32_t>();
        const draco::PointAttribute* attribute = mesh->GetAttributeByUniqueId(uniqueId);
        if (attribute == nullptr) {
            return Error{
                concat(what, ": Draco attribute id ", uniqueId, " is not in the compressed data")};
        }
        const int64_t count = index(**accessor, "count");
        if (count < 0 || uint64_t(count) != points) {
            return Error{concat(what, ": accessor ", accessorId, " has count ", count,
                                " but the decoded mesh has ", points, " points")};
        }
        const int components = componentsOf((*accessor)->value("type", std::string()));
        if (components == 0 || attribute->num_components() != components) {
            return Error{concat(what, ": accessor ", accessorId, " has type ",
                                (*accessor)->value("type", std::string("?")),
                                " but the Draco attribute has ", int(attribute->num_components()),
                                " components")};
        }
        const uint64_t size = points * uint64_t(components) * sizeof(float);
        if (auto charged = budget.charge(size, concat(what, ": ", points, " values")); !charged)
            return charged.error();
        std::vector<float> values(points * std::size_t(components));
        for (draco::PointIndex p(0); p < mesh->num_points(); ++p) {
            float* out = values.data() + std::size_t(p.value()) * std::size_t(components);
            if (!attribute->ConvertValue<float>(attribute->mapped_index(p), int8_t(components),
                                                out)) {
                return Error{concat(what, ": point ", p.value(), " cannot be read as float")};
            }
        }
        pointAccessor(**accessor, addView(views, decoded, newBuffer, values.data(), size), kFloat);
    }
    primitive["extensions"].erase(kName);
    if (primitive["extensions"].empty()) primitive.erase("extensions");
    return {};
}

}  // namespace

bool usesDracoCompression(const nlohmann::json& root) {
    const auto meshes = root.find("meshes");
    if (meshes == root.end() || !meshes->is_array()) return false;
    for (const nlohmann::json& mesh : *meshes) {
        if (!mesh.is_object() || !mesh.contains("primitives")) continue;
        const nlohmann::json& primitives = mesh["primitives"];
        if (!primitives.is_array()) continue;
        if (std::any_of(primitives.begin(), primitives.end(),
                        [](const nlohmann::json& p) { return dracoExtension(p) != nullptr; })) {
            return true;
        }
    }
    return false;
}

Expected<void> decodeDracoPrimitives(nlohmann::json& root, const std::string& folder,
                                     std::string_view glbBin, LoadBudget& budget) {
    nlohmann::json& buffers = root["buffers"];
    if (!buffers.is_array()) return Error{"buffers: expected an array"};
    if (!root.contains("bufferViews") || !root["bufferViews"].is_array())
        return Error{"bufferViews: expected an array"};
    Sources sources{folder, glbBin, std::vector<std::string>(buffers.size()),
                    std::vector<char>(buffers.size(), 0)};
    std::string decoded;
    const std::size_t newBuffer = buffers.size();
    nlohmann::json& meshes = root["meshes"];
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        nlohmann::json& mesh = meshes[m];
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
            continue;
        const std::string name = mesh.contains("name") && mesh["name"].is_string()
            ? concat(" (\"", mesh["name"].get<std::string>(), "\")")
            : std::string();
        nlohmann::json& primitives = mesh["primitives"];
        for (std::size_t p = 0; p < primitives.size(); ++p) {
            if (dracoExtension(primitives[p]) == nullptr) continue;
            const std::string where =
                concat("meshes[", m, "]", name, ".primitives[", p, "].extensions.", kName);
            if (auto ok = decodePrimitive(root, primitives[p], where, sources, decoded, newBuffer,
                                          budget);
                !ok) {
                return ok.error();
            }
        }
    }
    if (decoded.empty()) decoded.assign(4, '\0');  // tinygltf refuses an empty data: uri
    buffers.push_back({{"byteLength", decoded.size()}, {"uri", gltfDataUri(decoded)}});
    inlineBuffersAndDropExtensions(root, glbBin, {kName});
    return {};
}

}  // namespace daisy
