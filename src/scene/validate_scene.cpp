#include "scene/validate_scene.h"

#include <algorithm>
#include <cmath>

#include "core/strings.h"

namespace daisy {
namespace {

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
    }
    return {};
}

double longestEdgeSquared(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const Vec3d ab = b - a, bc = c - b, ca = a - c;
    return std::max({dot(ab, ab), dot(bc, bc), dot(ca, ca)});
}

}  // namespace

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

    std::size_t kept = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& triangle = mesh.triangles[t];
        for (uint32_t v : triangle) {
            if (v >= mesh.positions.size()) {
                return Error{concat(file, ": triangle ", t, " uses vertex ", v, " of ",
                                    mesh.positions.size())};
            }
        }
        if (mesh.materials[t] >= scene.materials.size()) {
            return Error{concat(file, ": triangle ", t, " uses material ", mesh.materials[t],
                                " of ", scene.materials.size())};
        }
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
    return {};
}

}  // namespace daisy
