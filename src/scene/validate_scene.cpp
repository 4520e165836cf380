#include "scene/validate_scene.h"

#include <algorithm>
#include <cmath>

#include "core/strings.h"

namespace daisy {
namespace {

// Larger RGB emission (factor x strength) would overflow the solve to infinity.
constexpr double kMaxEmissiveRgb = 1e30;

Expected<void> checkMaterial(const Material& material) {
    for (int k = 0; k < 3; ++k) {
        const double reflectance = material.baseColor[k];
        if (!std::isfinite(reflectance) || reflectance < 0 || reflectance > 1) {
            return Error{concat(material.origin, ": reflectance component ", k, " is ", reflectance,
                                ", outside [0, 1]")};
        }
        const double emission = material.emissiveRgb[k];
        if (!std::isfinite(emission) || emission < 0) {
            return Error{concat(material.origin, ": emission component ", k, " is ", emission,
                                ", must be finite and >= 0")};
        }
        if (emission > kMaxEmissiveRgb) {
            return Error{concat(material.origin, ": emission component ", k, " is ",
                                formatNumber(emission),
                                " (pi x emissiveFactor x emissiveStrength for glTF), over ",
                                formatNumber(kMaxEmissiveRgb), "; the solve would overflow")};
        }
    }
    return {};
}

double longestEdgeSquared(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const Vec3d ab = b - a, bc = c - b, ca = a - c;
    return std::max({dot(ab, ab), dot(bc, bc), dot(ca, ca)});
}

std::string formatPoint(const Vec3d& p) {
    return concat("(", formatNumber(p.x, 4), ", ", formatNumber(p.y, 4), ", ", formatNumber(p.z, 4),
                  ")");
}

double largestCoordinate(const Vec3d& p) {
    return std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
}

// True when some triangle uses an emissive material.
bool hasEmitter(const Scene& scene) {
    std::vector<char> emissive(scene.materials.size(), 0);
    for (std::size_t m = 0; m < scene.materials.size(); ++m)
        emissive[m] = scene.materials[m].isEmissive();
    for (uint32_t material : scene.mesh.materials) {
        if (material < emissive.size() && emissive[material]) return true;
    }
    return false;
}

}  // namespace

SceneExtent sceneExtent(const TriangleMesh& mesh) {
    SceneExtent extent;
    if (mesh.triangles.empty()) return extent;
    Vec3d low = mesh.positions[mesh.triangles[0][0]], high = low;
    for (const auto& triangle : mesh.triangles) {
        for (uint32_t v : triangle) {
            const Vec3d& p = mesh.positions[v];
            low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
            high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
            extent.largestCoordinate = std::max(extent.largestCoordinate, largestCoordinate(p));
        }
    }
    extent.low = low;
    extent.high = high;
    extent.diagonal = length(high - low);
    return extent;
}

namespace {

std::string describeExtent(const SceneExtent& extent) {
    return concat("the geometry spans ", formatPoint(extent.low), " to ", formatPoint(extent.high),
                  " (diagonal ", formatNumber(extent.diagonal, 4), ")");
}

Expected<void> checkLargestCoordinate(const std::string& file, const SceneExtent& extent) {
    if (extent.largestCoordinate <= kMaxSceneCoordinate) return {};
    return Error{concat(file, ": ", describeExtent(extent), "; coordinates up to ",
                        formatNumber(extent.largestCoordinate, 4), " exceed the ",
                        formatNumber(kMaxSceneCoordinate, 3),
                        " that float32 form factors and ray tracing represent; rescale the "
                        "scene (glTF units are metres)")};
}

}  // namespace

Expected<void> checkRayTracingRange(const Scene& scene) {
    const std::string& file = scene.path;
    if (scene.mesh.triangles.empty()) return {};
    const SceneExtent extent = sceneExtent(scene.mesh);
    const double size = extent.diagonal;
    const std::string box = describeExtent(extent);
    if (auto ok = checkLargestCoordinate(file, extent); !ok) return ok;
    if (size < kMinSceneDiagonal) {
        return Error{concat(file, ": ", box, ", under the ", formatNumber(kMinSceneDiagonal),
                            " that float32 form factors resolve (r^4 underflows); rescale the "
                            "scene (glTF units are metres)")};
    }
    if (extent.largestCoordinate > kMaxOffsetRatio * size) {
        return Error{concat(file, ": ", box, ", ", formatNumber(extent.largestCoordinate, 4),
                            " from the origin: more than ", formatNumber(kMaxOffsetRatio),
                            " times its size, so float32 positions cannot resolve it; move it "
                            "nearer the origin")};
    }
    const Vec3d centre = (extent.low + extent.high) * 0.5;
    for (const Camera& camera : scene.cameras) {
        const double distance = length(camera.position - centre);
        if (!isFinite(camera.position) ||
            largestCoordinate(camera.position) > kMaxSceneCoordinate ||
            distance > kMaxOffsetRatio * size) {
            return Error{concat(
                file, ": camera '", camera.name, "' at ", formatPoint(camera.position), " is ",
                formatNumber(distance, 4), " from the geometry's centre; the limit is ",
                formatNumber(kMaxOffsetRatio), " x the scene diagonal ", formatNumber(size, 4),
                " = ", formatNumber(kMaxOffsetRatio * size, 4), " (and coordinates up to ",
                formatNumber(kMaxSceneCoordinate, 3), ") for float32 ray tracing")};
        }
    }
    return {};
}

std::string noEmitterWarning(const Scene& scene) {
    if (hasEmitter(scene) || !scene.lights.empty()) return {};
    return concat(scene.path,
                  ": no surface emits light (no emissiveFactor, KHR_materials_emissive_strength "
                  "or DAISY_materials_spectral emission on any material in use): radiosity will "
                  "be zero everywhere and images black");
}

Expected<void> validateScene(Scene& scene) {
    TriangleMesh& mesh = scene.mesh;
    const std::string& file = scene.path;
    for (const Material& material : scene.materials) {
        if (auto ok = checkMaterial(material); !ok) return ok.error();
    }
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        if (!isFinite(mesh.positions[v])) {
            return Error{concat(file, ": vertex ", v, " has a non-finite world position ",
                                mesh.positions[v])};
        }
    }
    if (mesh.materials.size() != mesh.triangles.size()) {
        return Error{concat(file, ": ", mesh.triangles.size(), " triangles but ",
                            mesh.materials.size(), " material assignments")};
    }

    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (uint32_t v : mesh.triangles[t]) {
            if (v >= mesh.positions.size()) {
                return Error{concat(file, ": triangle ", t, " uses vertex ", v, " of ",
                                    mesh.positions.size())};
            }
        }
        if (mesh.materials[t] >= scene.materials.size()) {
            return Error{concat(file, ": triangle ", t, " uses material ", mesh.materials[t],
                                " of ", scene.materials.size())};
        }
    }
    // Before degenerate triangles are dropped: geometry moved far from the origin (a node
    // translated by 1e17) collapses to zero area in double and would vanish in silence.
    if (auto ok = checkLargestCoordinate(file, sceneExtent(mesh)); !ok) return ok;

    std::size_t kept = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& triangle = mesh.triangles[t];
        const Vec3d a = mesh.positions[triangle[0]];
        const Vec3d b = mesh.positions[triangle[1]];
        const Vec3d c = mesh.positions[triangle[2]];
        const double area2 = length(areaVector2(a, b, c));
        // Zero area up to rounding: |cross| <= 2e-14 x (longest edge)^2. A sliver of aspect
        // ratio 1e4 has |cross| ~ 1e-4 x edge^2 and is kept.
        if (!(area2 > 2e-14 * longestEdgeSquared(a, b, c))) continue;
        mesh.triangles[kept] = triangle;
        mesh.materials[kept] = mesh.materials[t];
        ++kept;
    }
    scene.degenerateDropped = mesh.triangles.size() - kept;
    mesh.triangles.resize(kept);
    mesh.materials.resize(kept);
    if (scene.degenerateDropped > 0) {
        scene.warnings.push_back(concat(file, ": dropped ", scene.degenerateDropped,
                                        " degenerate (zero-area) triangle",
                                        scene.degenerateDropped == 1 ? "" : "s"));
    }
    if (mesh.triangles.empty()) {
        return Error{concat(file, ": the scene has no triangles",
                            scene.degenerateDropped ? " with non-zero area" : "")};
    }
    if (auto ok = checkRayTracingRange(scene); !ok) return ok;
    if (std::string warning = noEmitterWarning(scene); !warning.empty()) {
        scene.warnings.push_back(std::move(warning));
    }
    return {};
}

}  // namespace daisy
