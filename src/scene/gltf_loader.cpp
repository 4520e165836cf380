#include "scene/gltf_loader.h"

#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <utility>
#include <vector>

#include "core/strings.h"
#include "scene/gltf_accessors.h"
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

// tinygltf's parsed JSON value as nlohmann::json (binary values cannot come from JSON: null).
nlohmann::json toJson(const tinygltf::Value& value) {
    switch (value.Type()) {
        case tinygltf::BOOL_TYPE:
            return value.Get<bool>();
        case tinygltf::INT_TYPE:
            return value.Get<int>();
        case tinygltf::REAL_TYPE:
            return value.Get<double>();
        case tinygltf::STRING_TYPE:
            return value.Get<std::string>();
        case tinygltf::ARRAY_TYPE: {
            nlohmann::json array = nlohmann::json::array();
            for (const tinygltf::Value& element : value.Get<tinygltf::Value::Array>()) {
                array.push_back(toJson(element));
            }
            return array;
        }
        case tinygltf::OBJECT_TYPE: {
            nlohmann::json object = nlohmann::json::object();
            for (const auto& [key, member] : value.Get<tinygltf::Value::Object>()) {
                object[key] = toJson(member);
            }
            return object;
        }
        default:
            return nullptr;
    }
}

Expected<Material> convertMaterial(const tinygltf::Material& source, int index,
                                   const std::string& path) {
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

    double strength = 1;
    if (auto it = source.extensions.find(kEmissiveStrengthName); it != source.extensions.end()) {
        const std::string strengthWhere =
            concat(where, ".extensions.", kEmissiveStrengthName, ".emissiveStrength");
        const tinygltf::Value& value =
            it->second.IsObject() ? it->second.Get("emissiveStrength") : tinygltf::Value();
        if (value.IsNumber()) {
            strength = value.GetNumberAsDouble();
        } else if (value.Type() != tinygltf::NULL_TYPE) {
            return Error{strengthWhere + ": not a number"};
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
        material.emissiveRgb[c] = factor * strength;
    }

    if (auto it = source.extensions.find(kSpectralExtensionName); it != source.extensions.end()) {
        auto spectral = parseMaterialExtension(
            toJson(it->second), concat(where, ".extensions.", kSpectralExtensionName));
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
    SceneBuilder(const tinygltf::Model& model, const std::string& path, Scene& scene)
        : model_(model), path_(path), scene_(scene) {}

    Expected<void> build() {
        for (std::size_t i = 0; i < model_.materials.size(); ++i) {
            auto material = convertMaterial(model_.materials[i], static_cast<int>(i), path_);
            if (!material) return material.error();
            scene_.materials.push_back(std::move(*material));
        }
        defaultMaterial_ = static_cast<uint32_t>(model_.materials.size());

        auto traversed = traverse();
        if (!traversed) return traversed;
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
                auto appended = appendMesh(node.mesh, world);
                if (!appended) return appended;
            }
            if (node.camera != -1) {
                auto added = addCamera(node, where, world);
                if (!added) return added;
            }
            for (std::size_t k = node.children.size(); k-- > 0;) {
                stack.push_back({node.children[k], world, concat(where, ".children[", k, "]")});
            }
        }
        return {};
    }

    Expected<void> appendMesh(int meshIndex, const Mat4& world) {
        const auto& primitives = model_.meshes[static_cast<std::size_t>(meshIndex)].primitives;
        for (std::size_t p = 0; p < primitives.size(); ++p) {
            auto appended = appendPrimitive(primitives[p], world);
            if (!appended) {
                return withContext(appended.error(),
                                   concat("meshes[", meshIndex, "].primitives[", p, "]"));
            }
        }
        return {};
    }

    Expected<void> appendPrimitive(const tinygltf::Primitive& primitive, const Mat4& world) {
        const int mode = primitive.mode == -1 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
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
        auto positions = readGltfPositions(model_, position->second);
        if (!positions) return withContext(positions.error(), "attributes.POSITION");
        const std::size_t vertexCount = positions->size();

        std::vector<uint32_t> indices;
        if (primitive.indices != -1) {
            auto read = readGltfIndices(model_, primitive.indices);
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

        TriangleMesh& mesh = scene_.mesh;
        if (vertexCount > std::numeric_limits<uint32_t>::max() - mesh.positions.size()) {
            return Error{"the scene has more vertices than 32-bit indices can address"};
        }
        const auto base = static_cast<uint32_t>(mesh.positions.size());
        for (const Vec3d& p : *positions)
            mesh.positions.push_back(transformPoint(world, p));
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
        scene_.cameras.push_back(std::move(camera));
        return {};
    }

    const tinygltf::Model& model_;
    const std::string& path_;
    Scene& scene_;
    uint32_t defaultMaterial_ = 0;
    bool usesDefault_ = false;
};

bool ignoreImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                 const unsigned char*, int, void*) {
    return true;
}

std::string trimNewlines(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r'))
        text.pop_back();
    return text;
}

// Parses the file with tinygltf: binary when it starts with the "glTF" magic or ends in .glb.
Expected<tinygltf::Model> parseFile(const std::string& path, std::vector<std::string>& warnings) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return Error{"cannot open the file"};
    char magic[4] = {};
    file.read(magic, sizeof(magic));
    const bool binary = (file.gcount() == 4 && std::memcmp(magic, "glTF", 4) == 0) ||
        std::filesystem::path(path).extension() == ".glb";
    file.close();

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&ignoreImage, nullptr);
    tinygltf::Model model;
    std::string error, warning;
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &error, &warning, path)
                           : loader.LoadASCIIFromFile(&model, &error, &warning, path);
    error = trimNewlines(error);
    warning = trimNewlines(warning);
    if (!ok || !error.empty()) {
        if (error.empty()) error = "tinygltf failed without a message";
        return Error{warning.empty() ? error : error + "; " + warning};
    }
    if (!warning.empty()) warnings.push_back(path + ": " + warning);
    return model;
}

}  // namespace

Expected<Scene> loadGltf(const std::string& path) {
    try {
        Scene scene;
        scene.path = path;
        auto model = parseFile(path, scene.warnings);
        if (!model) return withContext(model.error(), path);
        SceneBuilder builder(*model, path, scene);
        auto built = builder.build();
        if (!built) return withContext(built.error(), path);
        return scene;
    } catch (const std::exception& e) {
        return Error{path + ": " + e.what()};
    }
}

}  // namespace daisy
