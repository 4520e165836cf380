#include "scene/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "core/strings.h"
#include "scene/bounded_json.h"
#include "scene/gltf_accessors.h"
#include "scene/gltf_document.h"
#include "scene/gltf_draco.h"
#include "scene/gltf_features.h"
#include "scene/gltf_lights.h"
#include "scene/gltf_meshopt.h"
#include "scene/gltf_textures.h"
#include "scene/load_budget.h"
#include "scene/material_extension.h"

namespace daisy {
namespace {

constexpr const char* kEmissiveStrengthName = "KHR_materials_emissive_strength";

using Mat4 = GltfMatrix;  // column-major affine transform (gltf_accessors.h)

constexpr Mat4 kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 product{};
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            for (int k = 0; k < 4; ++k)
                product[4 * c + r] += a[4 * k + r] * b[4 * c + k];
        }
    }
    return product;
}

Vec3d transformVector(const Mat4& m, const Vec3d& v) {
    return {m[0] * v.x + m[4] * v.y + m[8] * v.z, m[1] * v.x + m[5] * v.y + m[9] * v.z,
            m[2] * v.x + m[6] * v.y + m[10] * v.z};
}

Vec3d transformPoint(const Mat4& m, const Vec3d& p) {
    return transformVector(m, p) + Vec3d{m[12], m[13], m[14]};
}

// Determinant of the linear part; negative for a mirroring transform.
double determinant3(const Mat4& m) {
    return dot(Vec3d{m[0], m[1], m[2]}, cross(Vec3d{m[4], m[5], m[6]}, Vec3d{m[8], m[9], m[10]}));
}

bool inRange(int index, std::size_t count) {
    return index >= 0 && static_cast<std::size_t>(index) < count;
}

// Member `key` of `object` when `object` is an object that has it, else nullptr.
const nlohmann::json* findMember(const nlohmann::json* object, const char* key) {
    if (object == nullptr || !object->is_object()) return nullptr;
    const auto it = object->find(key);
    return it == object->end() ? nullptr : &*it;
}

// `raw` is the material's object in the file's own JSON (bounded_json.h): the extensions are
// read from it, so numbers, nulls and empty members are seen as written.
Expected<Material> convertMaterial(const tinygltf::Material& source, const nlohmann::json* raw,
                                   int index, const std::string& path) {
    const std::string where = concat("materials[", index, "]");
    Material material;
    material.name = source.name.empty() ? concat("material", index) : source.name;
    material.origin = path + ": " + where;

    const std::string baseWhere = where + ".pbrMetallicRoughness.baseColorFactor";
    const std::vector<double>& base = source.pbrMetallicRoughness.baseColorFactor;
    if (base.size() != 4) {
        return Error{concat(baseWhere, ": has ", base.size(), " numbers, expected 4")};
    }
    for (std::size_t c = 0; c < 3; ++c) {
        if (!(base[c] >= 0 && base[c] <= 1)) {
            return Error{
                concat(baseWhere, "[", c, "]: ", formatNumber(base[c]), " is outside [0, 1]")};
        }
        material.baseColor[c] = base[c];
    }

    const nlohmann::json* extensions = findMember(raw, "extensions");
    if (extensions != nullptr && !extensions->is_object()) {
        return Error{
            concat(where, ".extensions: ", describeJson(*extensions), ", expected an object")};
    }
    double strength = 1;
    if (const nlohmann::json* object = findMember(extensions, kEmissiveStrengthName)) {
        const std::string strengthWhere =
            concat(where, ".extensions.", kEmissiveStrengthName, ".emissiveStrength");
        if (!object->is_object()) {
            return Error{concat(where, ".extensions.", kEmissiveStrengthName, ": ",
                                describeJson(*object), ", expected an object")};
        }
        if (const nlohmann::json* value = findMember(object, "emissiveStrength")) {
            if (!value->is_number()) {
                return Error{strengthWhere + ": " + describeJson(*value) + ", expected a number"};
            }
            strength = value->get<double>();
        }
        if (!(strength >= 0) || !std::isfinite(strength)) {
            return Error{
                concat(strengthWhere, ": ", formatNumber(strength), " is negative or not finite")};
        }
    }
    for (std::size_t c = 0; c < 3 && c < source.emissiveFactor.size(); ++c) {
        const double factor = source.emissiveFactor[c];
        if (!(factor >= 0) || !std::isfinite(factor)) {
            return Error{concat(where, ".emissiveFactor[", c, "]: ", formatNumber(factor),
                                " is negative or not finite")};
        }
        // glTF's emissive is radiance (KHR_materials_emissive_strength: in nits); a Lambertian
        // emitter of radiance L has exitance pi L (DESIGN.md section 2).
        // Clamped so an overflow reaches validate_scene's range check as a number.
        material.emissiveRgb[c] =
            std::min(std::numbers::pi * factor * strength, std::numeric_limits<double>::max());
    }

    if (const nlohmann::json* object = findMember(extensions, kSpectralExtensionName)) {
        auto spectral =
            parseMaterialExtension(*object, concat(where, ".extensions.", kSpectralExtensionName));
        if (!spectral) return spectral.error();
        material.spectral = std::move(*spectral);
    }
    return material;
}

const char* modeName(int mode) {
    static constexpr const char* kNames[] = {"POINTS",      "LINES",     "LINE_LOOP",
                                             "LINE_STRIP",  "TRIANGLES", "TRIANGLE_STRIP",
                                             "TRIANGLE_FAN"};
    return mode >= 0 && mode < 7 ? kNames[mode] : "unknown";
}

// Triangle corners (as positions in `indices`' values) for a TRIANGLES, TRIANGLE_STRIP or
// TRIANGLE_FAN primitive, ordered as glTF 2.0 section 3.7.2.1 specifies.
Expected<std::vector<std::array<uint32_t, 3>>> triangulate(int mode,
                                                           const std::vector<uint32_t>& indices) {
    const std::size_t n = indices.size();
    std::vector<std::array<uint32_t, 3>> triangles;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (n % 3 != 0) return Error{concat(n, " vertices do not make whole triangles")};
        for (std::size_t i = 0; i < n; i += 3) {
            triangles.push_back({indices[i], indices[i + 1], indices[i + 2]});
        }
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (std::size_t i = 0; i + 2 < n; ++i) {
            triangles.push_back({indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]});
        }
    } else {
        for (std::size_t i = 0; i + 2 < n; ++i) {
            triangles.push_back({indices[i + 1], indices[i + 2], indices[0]});
        }
    }
    return triangles;
}

// Flattens the default scene's node trees into a Scene. Messages lack the path; loadGltf adds it.
class SceneBuilder {
public:
    SceneBuilder(const tinygltf::Model& model, const nlohmann::json& root, const std::string& path,
                 Scene& scene, LoadBudget& budget)
        : model_(model), root_(root), path_(path), scene_(scene), budget_(budget) {}

    Expected<void> build() {
        const nlohmann::json* rawMaterials = findMember(&root_, "materials");
        for (std::size_t i = 0; i < model_.materials.size(); ++i) {
            const nlohmann::json* raw =
                rawMaterials != nullptr && rawMaterials->is_array() && i < rawMaterials->size()
                ? &(*rawMaterials)[i]
                : nullptr;
            auto material = convertMaterial(model_.materials[i], raw, static_cast<int>(i), path_);
            if (!material) return material.error();
            material->doubleSided = model_.materials[i].doubleSided;
            if (raw != nullptr) {
                if (auto textured = readTextures(*raw, static_cast<int>(i), *material); !textured)
                    return textured;
            }
            scene_.materials.push_back(std::move(*material));
        }
        defaultMaterial_ = static_cast<uint32_t>(model_.materials.size());

        auto lights = readGltfLights(root_);
        if (!lights) return lights.error();
        lights_ = std::move(*lights);
        auto traversed = traverse();
        if (!traversed) return traversed;
        // Vertices of primitives after the last one with an attribute get the default.
        for (auto& set : scene_.texCoords) {
            if (!set.empty()) set.resize(scene_.mesh.positions.size(), {0, 0});
        }
        if (!scene_.vertexColors.empty())
            scene_.vertexColors.resize(scene_.mesh.positions.size(), {1, 1, 1});
        if (usesDefault_) {
            // Not glTF's default: that is white (baseColorFactor 1), a perfect reflector under
            // which light in a closed room never decays and the radiosity solve cannot
            // converge. Material's 0.8 grey keeps such scenes physical.
            Material fallback;
            fallback.name = "default";
            fallback.origin = path_ + ": default material";
            scene_.materials.push_back(std::move(fallback));
        }
        return {};
    }

private:
    // baseColorTexture and emissiveTexture of material `index` (`raw` its JSON object). A base
    // colour texture that cannot be read leaves the factor times the default grey, not the
    // factor alone (often 1: a perfect reflector), with the warning naming the image.
    Expected<void> readTextures(const nlohmann::json& raw, int index, Material& material) {
        const std::string where = concat("materials[", index, "]");
        const nlohmann::json* pbr = findMember(&raw, "pbrMetallicRoughness");
        if (const nlohmann::json* info = findMember(pbr, "baseColorTexture")) {
            auto read = textures_.read(*info, where + ".pbrMetallicRoughness.baseColorTexture");
            if (!read) return read.error();
            material.baseColorTexture = read->ref;
            if (read->unreadable) {
                const Material fallback;
                for (std::size_t c = 0; c < 3; ++c)
                    material.baseColor[c] *= fallback.baseColor[c];
            }
        }
        if (const nlohmann::json* info = findMember(&raw, "emissiveTexture")) {
            auto read = textures_.read(*info, where + ".emissiveTexture");
            if (!read) return read.error();
            material.emissiveTexture = read->ref;
        }
        return {};
    }

    // Appends `count` values of TEXCOORD_<set> or COLOR_0 for the primitive's vertices (the
    // target array is first padded for earlier primitives without it).
    template <std::size_t N>
    Expected<void> appendAttribute(const tinygltf::Primitive& primitive, const std::string& name,
                                   std::size_t base, std::size_t count,
                                   std::vector<std::array<float, N>>& target,
                                   std::array<float, N> fallback) {
        const auto found = primitive.attributes.find(name);
        if (found == primitive.attributes.end()) {
            if (!target.empty()) target.resize(base + count, fallback);
            return {};
        }
        int components = static_cast<int>(N);
        if (N == 3 && inRange(found->second, model_.accessors.size()) &&
            model_.accessors[static_cast<std::size_t>(found->second)].type == TINYGLTF_TYPE_VEC4) {
            components = 4;  // RGBA colours: alpha is not modelled
        }
        auto values = readGltfAttribute(model_, found->second, components, budget_);
        if (!values) return withContext(values.error(), "attributes." + name);
        if (values->size() != count * std::size_t(components)) {
            return Error{concat("attributes.", name, ": ", values->size() / components,
                                " elements for ", count, " vertices")};
        }
        target.resize(base, fallback);
        for (std::size_t v = 0; v < count; ++v) {
            std::array<float, N> element{};
            for (std::size_t c = 0; c < N; ++c)
                element[c] = static_cast<float>((*values)[v * components + c]);
            target.push_back(element);
        }
        return {};
    }

    struct Pending {
        int node = 0;
        Mat4 parent;
        std::string where;  // the reference to the node, e.g. "nodes[2].children[0]"
    };

    // Depth-first over the default scene (or scene 0, or every root node), children in order.
    Expected<void> traverse() {
        std::vector<Pending> stack;
        int sceneIndex = model_.scenes.empty() ? -1 : 0;
        if (model_.defaultScene != -1) {
            if (!inRange(model_.defaultScene, model_.scenes.size())) {
                return Error{"scene: " +
                             gltfOutOfRange("scene", model_.defaultScene, model_.scenes.size())};
            }
            sceneIndex = model_.defaultScene;
        }
        if (sceneIndex >= 0) {
            const std::vector<int>& roots =
                model_.scenes[static_cast<std::size_t>(sceneIndex)].nodes;
            for (std::size_t k = roots.size(); k-- > 0;) {
                stack.push_back(
                    {roots[k], kIdentity, concat("scenes[", sceneIndex, "].nodes[", k, "]")});
            }
        } else {
            std::vector<char> isChild(model_.nodes.size(), 0);
            for (const tinygltf::Node& node : model_.nodes) {
                for (int child : node.children) {
                    if (inRange(child, isChild.size()))
                        isChild[static_cast<std::size_t>(child)] = 1;
                }
            }
            for (std::size_t n = model_.nodes.size(); n-- > 0;) {
                if (!isChild[n]) stack.push_back({static_cast<int>(n), kIdentity, "root nodes"});
            }
        }

        std::vector<char> visited(model_.nodes.size(), 0);
        while (!stack.empty()) {
            const Pending item = std::move(stack.back());
            stack.pop_back();
            if (!inRange(item.node, model_.nodes.size())) {
                return Error{item.where + ": " +
                             gltfOutOfRange("node", item.node, model_.nodes.size())};
            }
            const auto nodeIndex = static_cast<std::size_t>(item.node);
            const std::string where = concat("nodes[", item.node, "]");
            if (visited[nodeIndex]) {
                return Error{concat(where, " is reached a second time, from ", item.where,
                                    ": the node hierarchy has a cycle or a shared node, but "
                                    "glTF requires a tree")};
            }
            visited[nodeIndex] = 1;
            const tinygltf::Node& node = model_.nodes[nodeIndex];
            auto local = readGltfNodeTransform(model_, item.node);
            if (!local) return local.error();
            const Mat4 world = multiply(item.parent, *local);
            if (node.mesh != -1) {
                if (!inRange(node.mesh, model_.meshes.size())) {
                    return Error{where + ".mesh: " +
                                 gltfOutOfRange("mesh", node.mesh, model_.meshes.size())};
                }
                auto instances = instanceTransforms(nodeIndex, where);
                if (!instances) return instances.error();
                if (instances->empty()) {
                    auto appended = appendMesh(node.mesh, world);
                    if (!appended) return appended;
                }
                for (const Mat4& instance : *instances) {
                    auto appended = appendMesh(node.mesh, multiply(world, instance));
                    if (!appended) return appended;
                }
            }
            if (node.camera != -1) {
                auto added = addCamera(node, where, world);
                if (!added) return added;
            }
            if (const nlohmann::json* rawNodes = findMember(&root_, "nodes");
                rawNodes != nullptr && rawNodes->is_array() && nodeIndex < rawNodes->size()) {
                auto light = placeGltfLight((*rawNodes)[nodeIndex], lights_, world);
                if (!light) return withContext(light.error(), where);
                if (*light) scene_.lights.push_back(std::move(**light));
            }
            for (std::size_t k = node.children.size(); k-- > 0;) {
                stack.push_back({node.children[k], world, concat(where, ".children[", k, "]")});
            }
        }
        return {};
    }

    // EXT_mesh_gpu_instancing: node `nodeIndex`'s per-instance TRANSLATION, ROTATION (unit
    // quaternion) and SCALE, each instance's T R S (applied before the node's own transform);
    // empty without the extension.
    Expected<std::vector<Mat4>> instanceTransforms(std::size_t nodeIndex,
                                                   const std::string& where) {
        std::vector<Mat4> out;
        const nlohmann::json* rawNodes = findMember(&root_, "nodes");
        if (rawNodes == nullptr || !rawNodes->is_array() || nodeIndex >= rawNodes->size())
            return out;
        const nlohmann::json* extension = findMember(
            findMember(&(*rawNodes)[nodeIndex], "extensions"), "EXT_mesh_gpu_instancing");
        if (extension == nullptr) return out;
        const std::string extensionWhere = where + ".extensions.EXT_mesh_gpu_instancing";
        const nlohmann::json* attributes = findMember(extension, "attributes");
        if (attributes == nullptr || !attributes->is_object()) {
            return Error{extensionWhere + ".attributes: expected an object"};
        }
        std::array<std::vector<double>, 3> values;  // translation, rotation, scale
        const std::array<std::pair<const char*, int>, 3> kinds = {
            std::pair{"TRANSLATION", 3}, std::pair{"ROTATION", 4}, std::pair{"SCALE", 3}};
        std::size_t count = 0;
        bool any = false;
        for (std::size_t k = 0; k < kinds.size(); ++k) {
            const nlohmann::json* accessor = findMember(attributes, kinds[k].first);
            if (accessor == nullptr) continue;
            const std::string attributeWhere =
                concat(extensionWhere, ".attributes.", kinds[k].first);
            if (!accessor->is_number_integer())
                return Error{attributeWhere + ": expected an integer"};
            auto read = readGltfAttribute(model_, accessor->get<int>(), kinds[k].second, budget_);
            if (!read) return withContext(read.error(), attributeWhere);
            const std::size_t n = read->size() / std::size_t(kinds[k].second);
            if (any && n != count) {
                return Error{
                    concat(attributeWhere, ": ", n, " instances where the others have ", count)};
            }
            count = n;
            any = true;
            values[k] = std::move(*read);
        }
        if (auto charged = budget_.charge(count * sizeof(Mat4),
                                          concat(extensionWhere, ": ", count, " instances"));
            !charged) {
            return charged.error();
        }
        out.reserve(count);
        for (std::size_t i = 0; i < count; ++i) {
            std::array<double, 3> t{0, 0, 0}, scale{1, 1, 1};
            std::array<double, 4> q{0, 0, 0, 1};
            if (!values[0].empty()) std::copy_n(values[0].begin() + 3 * i, 3, t.begin());
            if (!values[1].empty()) std::copy_n(values[1].begin() + 4 * i, 4, q.begin());
            if (!values[2].empty()) std::copy_n(values[2].begin() + 3 * i, 3, scale.begin());
            auto m = gltfTrsMatrix(t, q, scale);
            if (!m) {
                return Error{
                    concat(extensionWhere, ": instance ", i, " rotation: ", m.error().message)};
            }
            out.push_back(*m);
        }
        return out;
    }

    Expected<void> appendMesh(int meshIndex, const Mat4& world) {
        const tinygltf::Mesh& mesh = model_.meshes[static_cast<std::size_t>(meshIndex)];
        const auto& primitives = mesh.primitives;
        std::vector<std::string> skippedModes;
        for (std::size_t p = 0; p < primitives.size(); ++p) {
            std::string skipped;
            auto appended = appendPrimitive(primitives[p], world, skipped);
            if (!appended) {
                return withContext(appended.error(),
                                   concat("meshes[", meshIndex, "].primitives[", p, "]"));
            }
            warnMissingTexCoords(meshIndex, p);
            if (!skipped.empty() &&
                std::find(skippedModes.begin(), skippedModes.end(), skipped) ==
                    skippedModes.end()) {
                skippedModes.push_back(skipped);
            }
        }
        // One line per mesh (a mesh instanced by many nodes is named once).
        if (!skippedModes.empty() && warnedMeshes_.insert(meshIndex).second) {
            std::string modes;
            for (const std::string& m : skippedModes) {
                if (!modes.empty()) modes += ", ";
                modes += m;
            }
            scene_.warnings.push_back(
                concat(path_, ": meshes[", meshIndex, "]",
                       mesh.name.empty() ? std::string() : " '" + mesh.name + "'", ": ", modes,
                       " primitives skipped (only triangles become patches)"));
        }
        return {};
    }

    // A texture of the primitive's material that reads a TEXCOORD_<n> the primitive does not have
    // is sampled at (0, 0) everywhere: one warning per primitive and set (instances share it).
    void warnMissingTexCoords(int meshIndex, std::size_t p) {
        const tinygltf::Primitive& primitive =
            model_.meshes[static_cast<std::size_t>(meshIndex)].primitives[p];
        if (!inRange(primitive.material, defaultMaterial_)) return;
        const Material& material = scene_.materials[static_cast<std::size_t>(primitive.material)];
        const std::pair<const char*, const std::optional<TextureRef>*> textures[] = {
            {"pbrMetallicRoughness.baseColorTexture", &material.baseColorTexture},
            {"emissiveTexture", &material.emissiveTexture}};
        for (const auto& [name, ref] : textures) {
            if (!ref->has_value() || (*ref)->texCoord > 1) continue;  // sets 2+ warn on load
            const std::string set = concat("TEXCOORD_", (*ref)->texCoord);
            if (primitive.attributes.count(set) != 0) continue;
            if (!warnedTexCoords_.insert({meshIndex, p, (*ref)->texCoord}).second) continue;
            scene_.warnings.push_back(
                concat(path_, ": meshes[", meshIndex, "].primitives[", p, "] has no ", set,
                       ", which ", "materials[", primitive.material, "].", name,
                       " reads: the texture is sampled at (0, 0) on the whole primitive"));
        }
    }

    // `skipped` is set to the mode's name when the primitive is points or lines.
    Expected<void> appendPrimitive(const tinygltf::Primitive& primitive, const Mat4& world,
                                   std::string& skipped) {
        const int mode = primitive.mode == -1 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
        if (mode >= TINYGLTF_MODE_POINTS && mode < TINYGLTF_MODE_TRIANGLES) {
            skipped = modeName(mode);  // points and lines have no area: no patch, no pixel
            return {};
        }
        if (mode < TINYGLTF_MODE_TRIANGLES || mode > TINYGLTF_MODE_TRIANGLE_FAN) {
            return Error{concat("mode ", mode, " (", modeName(mode),
                                ") is not supported: only triangles, strips and fans")};
        }
        uint32_t material = defaultMaterial_;
        if (primitive.material != -1) {
            if (!inRange(primitive.material, model_.materials.size())) {
                return Error{
                    gltfOutOfRange("material", primitive.material, model_.materials.size())};
            }
            material = static_cast<uint32_t>(primitive.material);
        }
        const auto position = primitive.attributes.find("POSITION");
        if (position == primitive.attributes.end()) return Error{"has no POSITION attribute"};
        auto positions = readGltfPositions(model_, position->second, budget_);
        if (!positions) return withContext(positions.error(), "attributes.POSITION");
        const std::size_t vertexCount = positions->size();

        std::vector<uint32_t> indices;
        if (primitive.indices != -1) {
            auto read = readGltfIndices(model_, primitive.indices, budget_);
            if (!read) return withContext(read.error(), "indices");
            indices = std::move(*read);
            for (std::size_t k = 0; k < indices.size(); ++k) {
                if (indices[k] >= vertexCount) {
                    return Error{concat("index ", indices[k], " at position ", k,
                                        " is out of range (accessor ", position->second, " has ",
                                        vertexCount, " vertices)")};
                }
            }
        } else {
            indices.resize(vertexCount);
            for (std::size_t k = 0; k < vertexCount; ++k)
                indices[k] = static_cast<uint32_t>(k);
        }
        auto triangles = triangulate(mode, indices);
        if (!triangles) return triangles.error();

        // The world-space copy: a position per vertex, corners and a material per triangle.
        const uint64_t meshBytes = uint64_t(vertexCount) * sizeof(Vec3d) +
            uint64_t(triangles->size()) * (3 * sizeof(uint32_t) + sizeof(uint32_t));
        if (auto charged = budget_.charge(
                meshBytes, concat(vertexCount, " vertices and ", triangles->size(), " triangles"));
            !charged) {
            return charged.error();
        }
        TriangleMesh& mesh = scene_.mesh;
        if (vertexCount > std::numeric_limits<uint32_t>::max() - mesh.positions.size()) {
            return Error{"the scene has more vertices than 32-bit indices can address"};
        }
        const auto base = static_cast<uint32_t>(mesh.positions.size());
        for (const Vec3d& p : *positions)
            mesh.positions.push_back(transformPoint(world, p));
        for (int set = 0; set < 2; ++set) {
            auto appended = appendAttribute<2>(primitive, concat("TEXCOORD_", set), base,
                                               vertexCount, scene_.texCoords[set], {0, 0});
            if (!appended) return appended;
        }
        if (auto appended = appendAttribute<3>(primitive, "COLOR_0", base, vertexCount,
                                               scene_.vertexColors, {1, 1, 1});
            !appended) {
            return appended;
        }
        // A mirroring transform turns counter-clockwise corners clockwise; swapping two corners
        // keeps the geometric normal on the side the file intends (glTF 2.0 section 3.7.4).
        const bool mirrored = determinant3(world) < 0;
        for (const auto& corners : *triangles) {
            const uint32_t b = base + corners[1], c = base + corners[2];
            mesh.triangles.push_back({base + corners[0], mirrored ? c : b, mirrored ? b : c});
            mesh.materials.push_back(material);
        }
        usesDefault_ = usesDefault_ || material == defaultMaterial_;
        return {};
    }

    Expected<void> addCamera(const tinygltf::Node& node, const std::string& where,
                             const Mat4& world) {
        if (!inRange(node.camera, model_.cameras.size())) {
            return Error{
                where + ".camera: " + gltfOutOfRange("camera", node.camera, model_.cameras.size())};
        }
        const tinygltf::Camera& source = model_.cameras[static_cast<std::size_t>(node.camera)];
        const std::string cameraWhere = concat("cameras[", node.camera, "]");
        if (source.type != "perspective") {
            scene_.warnings.push_back(concat(path_, ": ", where, ": ", cameraWhere, " is ",
                                             source.type,
                                             "; only perspective cameras are "
                                             "supported, so it is skipped"));
            scene_.skippedCameras.emplace_back(
                node.camera,
                concat(cameraWhere, source.name.empty() ? "" : " '" + source.name + "'", " (",
                       source.type, ")"));
            return {};
        }
        const tinygltf::PerspectiveCamera& lens = source.perspective;
        if (!(lens.yfov > 0 && lens.yfov < std::numbers::pi)) {
            return Error{concat(cameraWhere, ".perspective.yfov: ", formatNumber(lens.yfov),
                                " is outside (0, pi)")};
        }
        if (!(lens.aspectRatio >= 0) || !(lens.znear >= 0) || !(lens.zfar >= 0) ||
            !std::isfinite(lens.aspectRatio + lens.znear + lens.zfar)) {
            return Error{cameraWhere +
                         ".perspective: aspectRatio, znear and zfar must be "
                         "finite and non-negative"};
        }
        Camera camera;
        camera.name = !source.name.empty() ? source.name
            : !node.name.empty()           ? node.name
                                           : concat("camera", scene_.cameras.size());
        camera.position = transformPoint(world, {0, 0, 0});
        const Vec3d forward = transformVector(world, {0, 0, -1});
        const Vec3d up = transformVector(world, {0, 1, 0});
        const Vec3d upOrthogonal = up - forward * (dot(up, forward) / dot(forward, forward));
        if (!(length(forward) > 0) || !(length(upOrthogonal) > 0)) {
            return Error{where + ": the camera's transform is degenerate"};
        }
        camera.forward = normalize(forward);
        camera.up = normalize(upOrthogonal);
        camera.yFovRad = lens.yfov;
        camera.aspectRatio = lens.aspectRatio;
        if (lens.znear > 0) camera.zNear = lens.znear;
        camera.zFar = lens.zfar;
        camera.fileIndex = node.camera;
        scene_.cameras.push_back(std::move(camera));
        return {};
    }

    const tinygltf::Model& model_;
    const nlohmann::json& root_;
    const std::string& path_;
    Scene& scene_;
    LoadBudget& budget_;
    GltfTextures textures_{model_, path_, scene_, budget_};
    uint32_t defaultMaterial_ = 0;
    bool usesDefault_ = false;
    std::set<int> warnedMeshes_;
    std::set<std::tuple<int, std::size_t, int>> warnedTexCoords_;  // (mesh, primitive, set)
    std::vector<PunctualLight> lights_;  // the file's light list (KHR_lights_punctual)
};

std::string trimNewlines(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r'))
        text.pop_back();
    return text;
}

// The file's glTF, checked before tinygltf sees it (gltf_document.h, bounded_json.h).
struct ParsedFile {
    tinygltf::Model model;
    nlohmann::json root;  // the JSON as written
};

Expected<ParsedFile> parseFile(const std::string& path, LoadBudget& budget,
                               std::vector<std::string>& warnings) {
    std::error_code ec;
    const uint64_t fileBytes = std::filesystem::file_size(path, ec);
    if (ec) return Error{"cannot open the file"};
    if (auto charged = budget.charge(fileBytes, concat("the file (", fileBytes, " bytes)"));
        !charged) {
        return charged.error();
    }
    std::ifstream file(path, std::ios::binary);
    if (!file) return Error{"cannot open the file"};
    std::string bytes(fileBytes, '\0');
    file.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (static_cast<uint64_t>(file.gcount()) != fileBytes) return Error{"cannot read the file"};
    bool binary = (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) ||
        toLower(std::filesystem::path(path).extension().string()) == ".glb";

    std::string_view jsonText = bytes;
    GlbChunks chunks;
    if (binary) {
        auto split = splitGlb(bytes);
        if (!split) return split.error();
        chunks = *split;
        jsonText = chunks.json;
    }
    ParsedFile parsed;
    auto root = parseBoundedJson(jsonText);
    if (!root) return binary ? withContext(root.error(), "GLB chunk 0 (JSON)") : root.error();
    parsed.root = std::move(*root);
    if (auto ok = checkGltfAsset(parsed.root); !ok) return ok.error();
    const std::string folder = std::filesystem::path(path).parent_path().string();
    if (usesMeshoptCompression(parsed.root)) {
        // Decoded into plain glTF (a .gltf with data: buffers) before anything else reads it.
        if (auto ok = decodeMeshoptViews(parsed.root, folder, chunks.bin, budget); !ok) {
            return ok.error();
        }
        bytes = parsed.root.dump();
        binary = false;
        chunks = GlbChunks{};
    }
    if (usesDracoCompression(parsed.root)) {
        // KHR_draco_mesh_compression the same way: decoded primitives in a data: buffer.
        if (auto ok = decodeDracoPrimitives(parsed.root, folder, chunks.bin, budget); !ok) {
            return ok.error();
        }
        bytes = parsed.root.dump();
        binary = false;
        chunks = GlbChunks{};
    }
    if (auto ok = checkRequiredGltfExtensions(parsed.root); !ok) return ok.error();
    warnDroppedGltfFeatures(parsed.root, path, warnings);
    if (auto ok = checkGltfResources(parsed.root, folder, chunks.bin.size(), binary, budget); !ok) {
        return ok.error();
    }

    // The lights are read again by the scene builder; reading them here first gives their
    // errors a place (tinygltf says only "Spot light description not found.").
    if (auto lights = readGltfLights(parsed.root); !lights) return lights.error();

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&keepEncodedGltfImage, nullptr);
    std::string error, warning;
    const std::string baseDir = folder.empty() ? "." : folder;
    const bool ok = binary
        ? loader.LoadBinaryFromMemory(&parsed.model, &error, &warning,
                                      reinterpret_cast<const unsigned char*>(bytes.data()),
                                      static_cast<unsigned int>(bytes.size()), baseDir)
        : loader.LoadASCIIFromString(&parsed.model, &error, &warning, bytes.data(),
                                     static_cast<unsigned int>(bytes.size()), baseDir);
    error = trimNewlines(error);
    std::replace(error.begin(), error.end(), '\n', ';');
    warning = trimNewlines(warning);
    if (!ok || !error.empty()) {
        if (error.empty()) error = "tinygltf failed without a message";
        return Error{warning.empty() ? error : error + "; " + warning};
    }
    // tinygltf's warnings come as lines; each becomes one warning line.
    for (std::size_t start = 0; start < warning.size();) {
        std::size_t end = warning.find('\n', start);
        if (end == std::string::npos) end = warning.size();
        const std::string line = trimNewlines(warning.substr(start, end - start));
        // Unreadable images are reported once each, by name, where a material uses them
        // (gltf_textures.h).
        const bool aboutImage = line.find("for image[") != std::string::npos ||
            line.rfind("File not found", 0) == 0 || line.rfind("File read error", 0) == 0 ||
            line.find("image[") != std::string::npos;
        if (!line.empty() && !aboutImage) warnings.push_back(path + ": " + line);
        start = end + 1;
    }
    return parsed;
}

}  // namespace

Expected<Scene> loadGltf(const std::string& path, uint64_t maxMemoryBytes) {
    try {
        Scene scene;
        scene.path = path;
        LoadBudget budget(maxMemoryBytes);
        auto parsed = parseFile(path, budget, scene.warnings);
        if (!parsed) return withContext(parsed.error(), path);
        SceneBuilder builder(parsed->model, parsed->root, path, scene, budget);
        auto built = builder.build();
        if (!built) return withContext(built.error(), path);
        return scene;
    } catch (const std::bad_alloc&) {
        return Error{path +
                     ": out of memory while loading (raise --max-memory or simplify the "
                     "scene)"};
    } catch (const std::exception& e) {
        return Error{path + ": " + e.what()};
    }
}

}  // namespace daisy
