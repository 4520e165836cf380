#include "radiosity/patch_exposure.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "core/check.h"
#include "core/disjoint_sets.h"
#include "geometry/bounds.h"
#include "geometry/shared_vec.h"
#include "raycast/ray_caster.h"
#include "shared/sampling.h"

namespace daisy {

namespace {

constexpr int kDivisions = 4;  // 4 x 4 = 16 children
constexpr int kProbeRays = 5;  // along the normal and four at 45 degrees

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

namespace {

// The probes from a point with normal n: along n, four 45 degrees from it, and four at 80
// degrees between those (they leave from under a table).
std::array<shared::vec3, kProbeRays + 4> probeDirections(const shared::vec3& n) {
    shared::vec3 t1, t2;
    shared::orthonormalBasis(n, t1, t2);
    const float h = std::sqrt(0.5f);  // cos and sin of 45 degrees
    const float c80 = std::cos(1.3962634f), s80 = std::sin(1.3962634f) * h;
    return {n,
            n * h + t1 * h,
            n * h - t1 * h,
            n * h + t2 * h,
            n * h - t2 * h,
            n * c80 + (t1 + t2) * s80,
            n * c80 + (t1 - t2) * s80,
            n * c80 - (t1 + t2) * s80,
            n * c80 - (t1 - t2) * s80};
}

// A closed object may enclose a buried point only when it is at most this share of the scene's
// size (bounding-box diagonals): a column's base or a cupboard, not a room whose walls and
// ceiling were modelled as one closed mesh facing out.
constexpr double kEnclosingShare = 0.5;

// Per patch, its piece: the patches joined to it through shared vertices (a closed object's
// faces, both sides of a double-sided surface), and per piece whether it is small enough to
// enclose a buried point (kEnclosingShare).
struct Pieces {
    std::vector<uint32_t> of;  // per patch, its piece's smallest patch
    std::vector<uint8_t> small;  // per piece (indexed by that patch)
    std::vector<uint8_t> lit;  // per piece: it encloses a light (litPieces)
    double sceneDiagonal = 0;

    // The small piece whose authored back (the side its normal leaves from, single- or
    // double-sided) a ray along d meets at `hit`; else kNoPatch.
    uint32_t backFacing(const PatchMesh& patches, uint32_t hit, const shared::vec3& d) const {
        if (hit == kNoPatch) return kNoPatch;
        const uint32_t other = patches.backPatch[hit];
        const Vec3d& m = patches.normals[other == kNoBackPatch ? hit : std::min(hit, other)];
        const bool back = m.x * d.x + m.y * d.y + m.z * d.z > 0;
        return back && small[of[hit]] ? of[hit] : kNoPatch;
    }
};

Pieces connectedPieces(const PatchMesh& patches) {
    const std::size_t n = patches.patchCount();
    DisjointSets sets(n);
    for (uint32_t v = 0; v < patches.vertexCount(); ++v) {
        const std::span<const uint32_t> around = patches.patchesAtVertex(v);
        for (std::size_t k = 1; k < around.size(); ++k)
            sets.join(around[0], around[k]);
    }
    Pieces pieces;
    pieces.of.resize(n);
    std::vector<Bounds3d> bounds(n);
    Bounds3d scene;
    for (uint32_t p = 0; p < n; ++p) {
        pieces.of[p] = sets.find(p);
        for (const uint32_t c : patches.patches[p]) {
            bounds[pieces.of[p]].extend(patches.positions[c]);
            scene.extend(patches.positions[c]);
        }
    }
    pieces.sceneDiagonal = scene.diagonal();
    pieces.small.assign(n, 0);
    for (uint32_t p = 0; p < n; ++p)
        pieces.small[p] = bounds[p].diagonal() <= kEnclosingShare * scene.diagonal();
    pieces.lit.assign(n, 0);
    return pieces;
}

// The piece that encloses `origin`: at least 3/4 of the rays from it along `directions` meet
// that piece's authored back and none another small piece's (the rest may meet a face lying on
// one of its faces, a floor under a box's bottom, first); or kNoPatch.
uint32_t enclosingPiece(const RayCaster& tracer, const PatchMesh& patches, const Pieces& pieces,
                        const shared::vec3& origin, std::span<const shared::vec3> directions,
                        float margin) {
    std::array<Ray, 16> rays{};
    std::array<SurfaceHit, 16> hits{};
    DAISY_CHECK(directions.size() <= rays.size());
    for (std::size_t k = 0; k < directions.size(); ++k) {
        const shared::vec3& d = directions[k];
        rays[k] = {{origin.x, origin.y, origin.z}, {d.x, d.y, d.z}};
    }
    tracer.closestSurfaceHits({rays.data(), directions.size()}, {hits.data(), directions.size()},
                              margin);
    uint32_t piece = kNoPatch;
    std::size_t count = 0;
    for (std::size_t k = 0; k < directions.size(); ++k) {
        const uint32_t hit = pieces.backFacing(patches, hits[k].patch, directions[k]);
        if (hit == kNoPatch) continue;
        if (piece != kNoPatch && hit != piece) return kNoPatch;
        piece = hit;
        ++count;
    }
    return 4 * count >= 3 * directions.size() ? piece : kNoPatch;
}

// Marks the pieces that enclose a light, which light their insides: an emitting patch's
// centroid (probes along its normal, 45 and 80 degrees from it: a lamp's bulb under its shade)
// or a point or spot light's position (14 probes all round).
void litPieces(const RayCaster& tracer, const PatchMesh& patches, std::span<const uint8_t> emitters,
               std::span<const Vec3d> lightPositions, Pieces& pieces) {
    const double size = std::max(1e-30, pieces.sceneDiagonal);
    const float margin = float(1e-6 * size);
    std::vector<uint32_t> enclosing(patches.patchCount(), kNoPatch);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, emitters.size(), 64), [&](const auto& range) {
            for (std::size_t p = range.begin(); p != range.end(); ++p) {
                if (!emitters[p]) continue;
                const auto directions = probeDirections(toVec3(patches.normals[p]));
                enclosing[p] = enclosingPiece(tracer, patches, pieces, toVec3(patches.centroids[p]),
                                              directions, margin);
            }
        });
    for (const uint32_t piece : enclosing)
        if (piece != kNoPatch) pieces.lit[piece] = 1;
    // 14 directions spread over the sphere (a Fibonacci lattice: none along the axes or a box's
    // diagonals, where it would meet edges and corners).
    std::array<shared::vec3, 14> around{};
    for (std::size_t k = 0; k < around.size(); ++k) {
        const float z = 1 - (2 * float(k) + 1) / float(around.size());
        const float r = std::sqrt(1 - z * z), phi = 2.399963f * float(k);  // the golden angle
        around[k] = shared::vec3(r * std::cos(phi), r * std::sin(phi), z);
    }
    for (const Vec3d& light : lightPositions) {
        const uint32_t piece =
            enclosingPiece(tracer, patches, pieces, toVec3(light), around, margin);
        if (piece != kNoPatch) pieces.lit[piece] = 1;
    }
}

}  // namespace

Expected<PatchExposure> patchExposure(const PatchMesh& patches, std::span<const uint8_t> emitters,
                                      std::span<const Vec3d> lightPositions) {
    const std::size_t n = patches.patchCount();
    PatchExposure exposure;
    exposure.fraction.assign(n, 1.0f);
    exposure.exposedPoints.assign(n, uint16_t(0xffff));
    if (n == 0) return exposure;
    auto caster = makeRayCaster(patches, {.packetMode = PacketMode::Packet16, .robust = true});
    if (!caster) return withContext(caster.error(), "patch exposure");
    const RayCaster& tracer = **caster;
    Pieces pieces = connectedPieces(patches);
    litPieces(tracer, patches, emitters, lightPositions, pieces);
    std::vector<uint32_t> burier(n, kNoPatch);  // per patch: a piece burying a point of it
    constexpr uint32_t kOpen = kNoPatch;  // a probe that shows the point is not enclosed
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 64), [&](const auto& range) {
        std::array<Ray, kPatchQuadraturePoints * kProbeRays> rays{};
        std::array<SurfaceHit, kPatchQuadraturePoints * kProbeRays> hits{};
        std::array<int, kPatchQuadraturePoints> pending{};
        std::array<uint32_t, kPatchQuadraturePoints> enclosing{};
        std::array<uint8_t, kPatchQuadraturePoints> singleSidedSoFar{};
        for (std::size_t p = range.begin(); p != range.end(); ++p) {
            const auto& c = patches.patches[p];
            const shared::PatchGeometry t = shared::makePatchGeometry(
                toVec3(patches.positions[c[0]]), toVec3(patches.positions[c[1]]),
                toVec3(patches.positions[c[2]]));
            const shared::vec3 n0 = toVec3(patches.normals[p]);
            const auto directions = probeDirections(n0);
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
            const bool emits = !emitters.empty() && emitters[p];
            const auto enclosedBy = [&](const SurfaceHit& hit, const shared::vec3& d) {
                const uint32_t piece = pieces.backFacing(patches, hit.patch, d);
                return emits || piece == kOpen || pieces.lit[piece] ? kOpen : piece;
            };
            // A point is buried when all its probes meet back faces: of single-sided surfaces
            // (inside a closed object), or the authored backs of one small piece of surfaces
            // (inside a closed double-sided object, such as a column's base on the floor, which
            // the point sees from within). The probe along the normal settles most points
            // (open): the other four go only from those it does not, and the four at 80
            // degrees only from points still enclosed by one piece.
            for (int q = 0; q < kPatchQuadraturePoints; ++q) {
                const shared::vec3 x = points[std::size_t(q)];
                rays[std::size_t(q)] = {{x.x, x.y, x.z}, {n0.x, n0.y, n0.z}};
            }
            tracer.closestSurfaceHits({rays.data(), kPatchQuadraturePoints},
                                      {hits.data(), kPatchQuadraturePoints}, margin);
            uint16_t mask = 0;
            int count = 0;
            for (int q = 0; q < kPatchQuadraturePoints; ++q) {
                const SurfaceHit& hit = hits[std::size_t(q)];
                const uint32_t piece = enclosedBy(hit, n0);
                const bool singleSided = backOnly(hit, n0);
                if (singleSided || piece != kOpen) {
                    enclosing[std::size_t(count)] = piece;
                    singleSidedSoFar[std::size_t(count)] = singleSided;
                    pending[std::size_t(count++)] = q;
                } else {
                    mask = uint16_t(mask | (1u << q));
                }
            }
            // Probes in directions [first, last) from the pending points; keeps those whose
            // probes all meet the back faces above, and opens the others.
            const auto probe = [&](int first, int last) {
                std::size_t k = 0;
                for (int j = 0; j < count; ++j) {
                    const shared::vec3 x = points[std::size_t(pending[std::size_t(j)])];
                    for (int r = first; r < last; ++r) {
                        const shared::vec3 d = directions[std::size_t(r)];
                        rays[k++] = {{x.x, x.y, x.z}, {d.x, d.y, d.z}};
                    }
                }
                tracer.closestSurfaceHits({rays.data(), k}, {hits.data(), k}, margin);
                int kept = 0;
                for (int j = 0; j < count; ++j) {
                    bool singleSided = singleSidedSoFar[std::size_t(j)] != 0;
                    bool enclosed = enclosing[std::size_t(j)] != kOpen;
                    for (int r = first; r < last; ++r) {
                        const SurfaceHit& hit = hits[std::size_t(j * (last - first) + r - first)];
                        const shared::vec3 d = directions[std::size_t(r)];
                        singleSided = singleSided && backOnly(hit, d);
                        enclosed = enclosed && enclosedBy(hit, d) == enclosing[std::size_t(j)];
                    }
                    if (singleSided) continue;  // buried inside a single-sided closed object
                    if (enclosed) {
                        pending[std::size_t(kept)] = pending[std::size_t(j)];
                        singleSidedSoFar[std::size_t(kept)] = 0;  // the 80-degree probes: pieces
                        enclosing[std::size_t(kept++)] = enclosing[std::size_t(j)];
                    } else {
                        mask = uint16_t(mask | (1u << pending[std::size_t(j)]));
                    }
                }
                count = kept;
            };
            if (count > 0) probe(1, kProbeRays);
            if (count > 0) probe(kProbeRays, kProbeRays + 4);
            if (count > 0) burier[p] = enclosing[0];
            exposure.exposedPoints[p] = mask;
            exposure.fraction[p] = float(std::popcount(unsigned(mask))) / kPatchQuadraturePoints;
        }
    });
    // The inner faces of a piece that buries a point (the back patches of its double-sided
    // faces, facing its inside) are buried too: no light reaches them, and a patch running
    // under the piece sees them from its buried part only (exposed_system.h: unburiedRowSums).
    std::vector<uint8_t> encloses(n, 0);
    for (const uint32_t piece : burier)
        if (piece != kOpen) encloses[piece] = 1;
    for (std::size_t p = 0; p < n; ++p) {
        const uint32_t front = patches.backPatch[p];
        if (front != kNoBackPatch && front < p && encloses[pieces.of[p]]) {
            exposure.exposedPoints[p] = 0;
            exposure.fraction[p] = 0;
        }
    }
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
