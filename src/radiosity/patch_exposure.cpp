#include "radiosity/patch_exposure.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "core/check.h"
#include "geometry/shared_vec.h"
#include "raycast/ray_caster.h"
#include "shared/sampling.h"

namespace daisy {

namespace {

constexpr int kDivisions = 4;  // 4 x 4 = 16 children
constexpr int kProbeRays = 5;

// The 16 children in order: (a, b) on the grid of upward children (a + b <= 3), each followed
// by the downward one beside it (a + b <= 2). A child's corners, as barycentric weights of the
// patch's corners b and c, are (a, b), (a + 1, b), (a, b + 1) over kDivisions when upward and
// (a + 1, b + 1), (a, b + 1), (a + 1, b) when downward.
struct Child {
    int a, b;
    bool down;
};
constexpr std::array<Child, kPatchQuadraturePoints> kChildren = [] {
    std::array<Child, kPatchQuadraturePoints> children{};
    int q = 0;
    for (int a = 0; a < kDivisions; ++a) {
        for (int b = 0; a + b < kDivisions; ++b) {
            children[std::size_t(q++)] = {a, b, false};
            if (a + b < kDivisions - 1) children[std::size_t(q++)] = {a, b, true};
        }
    }
    return children;
}();

// Barycentric weights of corners b and c of the children's centroids.
constexpr std::array<std::array<float, 2>, kPatchQuadraturePoints> kBarycentrics = [] {
    std::array<std::array<float, 2>, kPatchQuadraturePoints> points{};
    for (std::size_t q = 0; q < kChildren.size(); ++q) {
        const float third = kChildren[q].down ? 2.0f / 3 : 1.0f / 3;
        points[q] = {(kChildren[q].a + third) / kDivisions, (kChildren[q].b + third) / kDivisions};
    }
    return points;
}();

}  // namespace

shared::vec3 patchQuadraturePoint(const shared::PatchGeometry& t, int q) {
    const auto [u, v] = kBarycentrics[std::size_t(q)];
    return t.a * (1 - u - v) + t.b * u + t.c * v;
}

shared::vec3 pointInPatchChild(shared::vec3 a, shared::vec3 b, shared::vec3 c, int q,
                               shared::vec2 u) {
    const Child& child = kChildren[std::size_t(q)];
    const float s = 1.0f / kDivisions, ca = float(child.a) * s, cb = float(child.b) * s;
    // The child's corners, at barycentric weights (wb, wc) of b and c.
    const auto at = [&](float wb, float wc) { return a * (1 - wb - wc) + b * wb + c * wc; };
    if (child.down) {
        return shared::uniformPointOnTriangle(at(ca + s, cb + s), at(ca, cb + s), at(ca + s, cb),
                                              u);
    }
    return shared::uniformPointOnTriangle(at(ca, cb), at(ca + s, cb), at(ca, cb + s), u);
}

Expected<PatchExposure> patchExposure(const PatchMesh& patches) {
    const std::size_t n = patches.patchCount();
    PatchExposure exposure;
    exposure.fraction.assign(n, 1.0f);
    exposure.exposedPoints.assign(n, uint16_t(0xffff));
    if (n == 0) return exposure;
    auto caster = makeRayCaster(patches, {.packetMode = PacketMode::Packet16, .robust = true});
    if (!caster) return withContext(caster.error(), "patch exposure");
    const RayCaster& tracer = **caster;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 64), [&](const auto& range) {
        std::array<Ray, kPatchQuadraturePoints * kProbeRays> rays{};
        std::array<SurfaceHit, kPatchQuadraturePoints * kProbeRays> hits{};
        std::array<int, kPatchQuadraturePoints> pending{};
        for (std::size_t p = range.begin(); p != range.end(); ++p) {
            const auto& c = patches.patches[p];
            const shared::PatchGeometry t = shared::makePatchGeometry(
                toVec3(patches.positions[c[0]]), toVec3(patches.positions[c[1]]),
                toVec3(patches.positions[c[2]]));
            const shared::vec3 n0 = toVec3(patches.normals[p]);
            shared::vec3 t1, t2;
            shared::orthonormalBasis(n0, t1, t2);
            const float h = std::sqrt(0.5f);  // cos and sin of 45 degrees
            const std::array<shared::vec3, kProbeRays> directions = {
                n0, n0 * h + t1 * h, n0 * h - t1 * h, n0 * h + t2 * h, n0 * h - t2 * h};
            std::array<shared::vec3, kPatchQuadraturePoints> points;
            for (int q = 0; q < kPatchQuadraturePoints; ++q)
                points[std::size_t(q)] = patchQuadraturePoint(t, q);
            // Past the patch's own plane by a millionth of its size (its own triangle and its
            // coplanar neighbours are never hit).
            const float margin = 1e-6f * std::sqrt(std::max(t.area, 1e-30f)) +
                1e-6f * std::max({std::abs(t.a.x), std::abs(t.a.y), std::abs(t.a.z)});
            // Whether the probe ray hit the back of a single-sided surface (else the point is
            // open there: a miss, a front face or a double-sided surface).
            const auto backOnly = [&](const SurfaceHit& hit, const shared::vec3& d) {
                if (hit.patch == kNoPatch || patches.backPatch[hit.patch] != kNoBackPatch) {
                    return false;
                }
                const Vec3d& m = patches.normals[hit.patch];
                return m.x * d.x + m.y * d.y + m.z * d.z > 0;
            };
            // A point is buried when all its probes meet back faces. The one along the normal
            // settles most points (open): the other four go only from those it does not.
            for (int q = 0; q < kPatchQuadraturePoints; ++q) {
                const shared::vec3 x = points[std::size_t(q)];
                rays[std::size_t(q)] = {{x.x, x.y, x.z}, {n0.x, n0.y, n0.z}};
            }
            tracer.closestSurfaceHits({rays.data(), kPatchQuadraturePoints},
                                      {hits.data(), kPatchQuadraturePoints}, margin);
            uint16_t mask = 0;
            int count = 0;
            for (int q = 0; q < kPatchQuadraturePoints; ++q) {
                if (backOnly(hits[std::size_t(q)], n0)) {
                    pending[std::size_t(count++)] = q;
                } else {
                    mask = uint16_t(mask | (1u << q));
                }
            }
            if (count > 0) {
                std::size_t k = 0;
                for (int j = 0; j < count; ++j) {
                    const shared::vec3 x = points[std::size_t(pending[std::size_t(j)])];
                    for (int r = 1; r < kProbeRays; ++r) {
                        const shared::vec3 d = directions[std::size_t(r)];
                        rays[k++] = {{x.x, x.y, x.z}, {d.x, d.y, d.z}};
                    }
                }
                tracer.closestSurfaceHits({rays.data(), k}, {hits.data(), k}, margin);
                for (int j = 0; j < count; ++j) {
                    bool buried = true;
                    for (int r = 1; r < kProbeRays && buried; ++r) {
                        buried = backOnly(hits[std::size_t(j * (kProbeRays - 1) + r - 1)],
                                          directions[std::size_t(r)]);
                    }
                    if (!buried) mask = uint16_t(mask | (1u << pending[std::size_t(j)]));
                }
            }
            exposure.exposedPoints[p] = mask;
            exposure.fraction[p] = float(std::popcount(unsigned(mask))) / kPatchQuadraturePoints;
        }
    });
    return exposure;
}

std::vector<double> exposedAreas(const PatchMesh& patches, const PatchExposure& exposure) {
    DAISY_CHECK(exposure.fraction.size() == patches.patchCount());
    std::vector<double> areas(patches.patchCount());
    for (std::size_t p = 0; p < areas.size(); ++p)
        areas[p] = patches.areas[p] * exposure.fraction[p];
    return areas;
}

}  // namespace daisy
