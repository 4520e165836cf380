#include "hierarchical/hierarchical_transport.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "core/disjoint_sets.h"
#include "core/strings.h"
#include "geometry/shared_vec.h"
#include "radiosity/gather_kernels.h"
#include "radiosity/matrix_transport.h"
#include "radiosity/ray_pair_evaluator.h"
#include "raycast/ray_caster.h"
#include "shared/rng.h"
#include "shared/sampling.h"

namespace daisy {

HierarchicalTransport::HierarchicalTransport(const PatchMesh& mesh, ClusterTree tree,
                                             HierarchicalLinks links, std::vector<float> exposure,
                                             const std::vector<uint8_t>& enclosed)
    : tree_(std::move(tree)),
      near_(std::move(links.near)),
      stats_(links.stats),
      far_(std::move(links.far)),
      normals_(mesh.normals),
      areas_(mesh.areas),
      exposure_(std::move(exposure)) {
    const uint32_t n = near_.size;
    prepareNodes();
    farScale_.assign(n, 1.0);
    // Row sums: G for B = 1 at one wavelength.
    const std::vector<double> ones(n, 1.0);
    rowSums_.assign(n, 0.0);
    farGather(ones, 1, rowSums_);
    const std::vector<double> nearSums = daisy::rowSums(near_);
    for (uint32_t i = 0; i < n; ++i) {
        const double far = rowSums_[i], near = nearSums[i], sum = far + near;
        const uint8_t kind = enclosed.empty() ? 0 : enclosed[i];
        const bool closed =
            kind == kEnclosed || (kind == kEnclosedInOpenRegion && sum >= 1 - kOpenFill);
        rowSums_[i] = sum;
        if (!(sum > 1 || (closed && sum > 0))) continue;
        rowSums_[i] = 1;
        // The near factors are F's own: the far part takes what is left of 1 when it can.
        if (far > 0 && near < 1) {
            farScale_[i] = (1 - near) / far;
            continue;
        }
        const double scale = 1 / sum;
        farScale_[i] = scale;
        for (uint64_t e = near_.rowOffsets[i]; e < near_.rowOffsets[i + 1]; ++e)
            near_.values[e] = static_cast<float>(near_.values[e] * scale);
    }
}

HierarchicalTransport::HierarchicalTransport(const PatchMesh& mesh, HierarchicalParts parts)
    : tree_(std::move(parts.tree)),
      near_(std::move(parts.near)),
      stats_(parts.stats),
      far_(std::move(parts.far)),
      normals_(mesh.normals),
      areas_(mesh.areas),
      exposure_(std::move(parts.exposure)),
      farScale_(std::move(parts.farScale)),
      rowSums_(std::move(parts.rowSums)) {
    if (checkTree().empty()) prepareNodes();
}

void HierarchicalTransport::prepareNodes() {
    // A planar node's patches share one normal (cluster_tree.h; a node's children are planar
    // when it is): its far links need the scalar form only. Leaves use the patch's own normal.
    orientation_ = gatherOrientations(tree_, normals_);
    slot_ = gatherSlots(orientation_);
    DAISY_CHECK(slot_.back() < FarHalfLinks::kPlanarSource);
}

TransportStats HierarchicalTransport::stats() const {
    return {near_.nonzeroCount() + far_.count(),
            near_.bytes() + far_.bytes() + tree_.bytes() + orientation_.size() * sizeof(Vec3d) +
                slot_.size() * sizeof(uint64_t) + (normals_.size() * sizeof(Vec3d)) +
                2 * areas_.size() * sizeof(double) + exposure_.size() * sizeof(float)};
}

std::string HierarchicalTransport::checkTree() const {
    if (std::string near = validateStructure(near_); !near.empty()) return near;
    const std::size_t n = near_.size, nodes = tree_.nodes.size();
    if (normals_.size() != n || tree_.order.size() != n || tree_.leafOf.size() != n ||
        farScale_.size() != n || rowSums_.size() != n || exposure_.size() != n ||
        nodes != (n > 0 ? 2 * n - 1 : 0)) {
        return concat("the tree or the per-patch arrays do not match the ", n, " patches");
    }
    for (std::size_t k = 0; k < nodes; ++k) {
        const HierarchyNode& node = tree_.nodes[k];
        const bool inside = node.count >= 1 && node.first < n && node.count <= n - node.first;
        const bool leaf = inside && node.isLeaf() && tree_.order[node.first] < n;
        const bool inner = inside && !node.isLeaf() && node.children[0] > k &&
            node.children[1] > k && node.children[0] < nodes && node.children[1] < nodes;
        if (!leaf && !inner) return concat("tree node ", k, " is out of range");
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(farScale_[i]) || !std::isfinite(rowSums_[i]) ||
            !(exposure_[i] >= 0 && exposure_[i] <= 1)) {
            return concat("patch ", i,
                          " has a far scale or row sum that is not finite, or an exposed share "
                          "outside [0, 1]");
        }
    }
    return "";
}

std::string HierarchicalTransport::checkStructure() const {
    if (std::string tree = checkTree(); !tree.empty()) return tree;
    const std::size_t nodes = tree_.nodes.size();
    const auto offsetsHold = [nodes](const std::vector<uint64_t>& offsets, std::size_t size) {
        if (offsets.size() != nodes + 1 || offsets.front() != 0 || offsets.back() != size)
            return false;
        for (std::size_t k = 0; k < nodes; ++k) {
            if (offsets[k] > offsets[k + 1]) return false;
        }
        return true;
    };
    if (!offsetsHold(far_.planarOffsets, far_.planarSlots.size()) ||
        far_.planarWeights.size() != far_.planarSlots.size() ||
        !offsetsHold(far_.otherOffsets, far_.others.size())) {
        return "far-link offsets do not match the tree or the links";
    }
    // What starts at each slot: 1 a planar node's values, 2 another node's, 0 nothing.
    std::vector<uint8_t> starts(slot_[nodes], 0);
    for (std::size_t k = 0; k < nodes; ++k)
        starts[slot_[k]] = isPlanar(k) ? 1 : 2;
    for (std::size_t k = 0; k < nodes; ++k) {
        if (!isPlanar(k) && far_.planarOffsets[k] != far_.planarOffsets[k + 1])
            return concat("tree node ", k, " is not planar but has planar far links");
        for (uint64_t e = far_.planarOffsets[k]; e < far_.planarOffsets[k + 1]; ++e) {
            const uint32_t slot = far_.planarSlots[e];
            if (slot >= starts.size() || starts[slot] != 1 ||
                !std::isfinite(far_.planarWeights[e])) {
                return concat("planar far link ", e, " has slot ", slot, " and weight ",
                              far_.planarWeights[e]);
            }
        }
        for (uint64_t e = far_.otherOffsets[k]; e < far_.otherOffsets[k + 1]; ++e) {
            const FarHalfLinks::OtherLink& link = far_.others[e];
            const bool planarSource = link.planarSource();
            const uint32_t slot = link.source();
            const bool finite =
                std::isfinite(link.v[0]) && std::isfinite(link.v[1]) && std::isfinite(link.v[2]);
            if (slot >= starts.size() || starts[slot] != (planarSource ? 1 : 2) || !finite ||
                (planarSource && isPlanar(k))) {
                return concat("far link ", e, " has slot ", link.slot,
                              " or a vector that is not finite");
            }
        }
    }
    return "";
}

void HierarchicalTransport::farGather(std::span<const double> radiosity,
                                      std::size_t wavelengthCount, std::span<double> gathered,
                                      std::span<const uint8_t> sourceSlots) const {
    const std::size_t m = wavelengthCount, nodes = tree_.nodes.size();
    DAISY_CHECK(radiosity.size() == normals_.size() * m && gathered.size() == radiosity.size());
    if (nodes == 0) return;
    // Per node, m values for a planar node (the scalar form) or 3 m (the vector form), at
    // slot_[k] x m: the same layout for the pull and the push values.
    const std::size_t size = slot_[nodes] * m;
    std::unique_lock lock(workspaceMutex_, std::try_to_lock);
    std::vector<float> ownPull;
    std::vector<double> ownPush;
    std::vector<float>& pull = lock.owns_lock() ? pullWorkspace_ : ownPull;
    std::vector<double>& push = lock.owns_lock() ? pushWorkspace_ : ownPush;
    pull.resize(size);
    push.assign(size, 0.0);
    const auto at = [m](auto& values, std::size_t slot) { return values.data() + slot * m; };
    // Pull: children before parents. A planar node holds Q = sum A_j phi_j B_j (its P is n Q).
    const auto pullNode = [&](std::size_t k) {
        const HierarchyNode& node = tree_.nodes[k];
        float* p = at(pull, slot_[k]);
        if (!sourceSlots.empty() && !sourceSlots[slot_[k]]) {  // no source below: 0, unread
            std::fill(p, p + (isPlanar(k) ? m : 3 * m), 0.0f);
            return;
        }
        if (node.isLeaf()) {
            const uint32_t patch = tree_.order[node.first];
            const double a = areas_[patch] * exposure_[patch];
            const double* b = radiosity.data() + patch * m;
            for (std::size_t c = 0; c < m; ++c)
                p[c] = float(a * b[c]);
            return;
        }
        const float* p0 = at(pull, slot_[node.children[0]]);
        const float* p1 = at(pull, slot_[node.children[1]]);
        if (isPlanar(k)) {
            for (std::size_t c = 0; c < m; ++c)
                p[c] = p0[c] + p1[c];
            return;
        }
        std::fill(p, p + 3 * m, 0.0f);
        for (const uint32_t child : node.children) {
            const float* q = at(pull, slot_[child]);
            if (!isPlanar(child)) {
                for (std::size_t c = 0; c < 3 * m; ++c)
                    p[c] += q[c];
                continue;
            }
            const auto n = toVec3(orientation_[child]);
            for (std::size_t c = 0; c < m; ++c)
                p[c] += n.x * q[c], p[m + c] += n.y * q[c], p[2 * m + c] += n.z * q[c];
        }
    };
    visitSubtrees(tree_, pullNode, true);
    // Links: each receiving node sums its half-links, s = -K (u . P_S) per wavelength; a planar
    // receiver keeps n_R . J = sum s (u . n_R), another J = sum s u. Between two planar nodes
    // that is one weight times Q_S (FarHalfLinks::planarWeights), summed by the solver's
    // vectorised kernel in the pairs' fixed order (one by one, skipping, with sourceSlots);
    // the others apply their vector (FarHalfLinks::OtherLink).
    const AccumulateFn<float> accumulate = accumulateFor<float>(m);
    // The vector-form links' sources are up to 3 m values: fewer ahead than the kernels'.
    constexpr uint64_t kOtherPrefetchAhead = kPrefetchAhead / 2;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, nodes, 256),
        [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t k = range.begin(); k != range.end(); ++k) {
                double* __restrict j = at(push, slot_[k]);
                if (!sourceSlots.empty()) {
                    for (uint64_t e = far_.planarOffsets[k]; e < far_.planarOffsets[k + 1]; ++e) {
                        if (!sourceSlots[far_.planarSlots[e]]) continue;
                        const float* __restrict p = at(pull, far_.planarSlots[e]);
                        const double w = far_.planarWeights[e];
                        for (std::size_t c = 0; c < m; ++c)
                            j[c] += w * p[c];
                    }
                } else if (far_.planarOffsets[k] < far_.planarOffsets[k + 1]) {
                    accumulate(far_.planarSlots.data(), far_.planarWeights.data(),
                               far_.planarOffsets[k], far_.planarOffsets[k + 1], pull.data(), m, j);
                }
                const bool planarReceiver = isPlanar(k);
                for (uint64_t o = far_.otherOffsets[k]; o < far_.otherOffsets[k + 1]; ++o) {
                    if (o + kOtherPrefetchAhead < far_.otherOffsets[k + 1]) {
                        const FarHalfLinks::OtherLink& ahead = far_.others[o + kOtherPrefetchAhead];
                        prefetchRow(at(pull, ahead.source()), ahead.planarSource() ? m : 3 * m);
                    }
                    const FarHalfLinks::OtherLink& link = far_.others[o];
                    if (!sourceSlots.empty() && !sourceSlots[link.source()]) {
                        continue;
                    }
                    const float* __restrict p = at(pull, link.source());
                    const double x = link.v[0], y = link.v[1], z = link.v[2];
                    if (link.planarSource()) {
                        for (std::size_t c = 0; c < m; ++c) {
                            const double q = p[c];
                            j[c] += x * q, j[m + c] += y * q, j[2 * m + c] += z * q;
                        }
                    } else if (planarReceiver) {
                        for (std::size_t c = 0; c < m; ++c)
                            j[c] += x * p[c] + y * p[m + c] + z * p[2 * m + c];
                    } else {
                        for (std::size_t c = 0; c < m; ++c) {
                            const double s = -(x * p[c] + y * p[m + c] + z * p[2 * m + c]);
                            j[c] += s * x, j[m + c] += s * y, j[2 * m + c] += s * z;
                        }
                    }
                }
            }
        });
    // Push: parents before children, a planar child taking n . J of a vector parent; each
    // patch's leaf holds its irradiance.
    const auto pushNode = [&](std::size_t k) {
        const HierarchyNode& node = tree_.nodes[k];
        const double* j = at(push, slot_[k]);
        if (node.isLeaf()) {
            const uint32_t patch = tree_.order[node.first];
            const double scale = farScale_[patch] * exposure_[patch];
            double* g = gathered.data() + patch * m;
            for (std::size_t c = 0; c < m; ++c)
                g[c] = scale * j[c];
            return;
        }
        for (const uint32_t child : node.children) {
            double* d = at(push, slot_[child]);
            if (isPlanar(k) || !isPlanar(child)) {
                for (std::size_t c = 0; c < (isPlanar(k) ? m : 3 * m); ++c)
                    d[c] += j[c];
                continue;
            }
            const Vec3d& n = orientation_[child];
            for (std::size_t c = 0; c < m; ++c)
                d[c] += n.x * j[c] + n.y * j[m + c] + n.z * j[2 * m + c];
        }
    };
    visitSubtrees(tree_, pushNode, false);
}

void HierarchicalTransport::gather(std::span<const double> radiosity, std::size_t wavelengthCount,
                                   std::span<double> gathered, int threads) const {
    if (threads > 0) {
        tbb::task_arena arena(threads);
        arena.execute([&] { gather(radiosity, wavelengthCount, gathered, 0); });
        return;
    }
    std::vector<double> far(gathered.size());
    farGather(radiosity, wavelengthCount, far);
    gatherAll(near_, radiosity, wavelengthCount, gathered, 0);
    for (std::size_t e = 0; e < gathered.size(); ++e)
        gathered[e] += far[e];
}

void HierarchicalTransport::gatherFrom(std::span<const uint8_t> sources,
                                       std::span<const uint8_t> receivers,
                                       std::span<const double> radiosity,
                                       std::size_t wavelengthCount,
                                       std::span<double> gathered) const {
    const std::size_t n = patchCount(), m = wavelengthCount;
    DAISY_CHECK(sources.size() == n && receivers.size() == n && radiosity.size() == n * m &&
                gathered.size() == n * m);
    // The far links from nodes with a source below them only: a few emitters' light (the
    // direct light the image's final gather takes out) comes through a small part of them.
    // The sources' radiosity is read where it is: farGather takes the others' as 0, and so do
    // the near rows below, with no masked copy of B and no full arrays of the near part or the
    // sum (370 MB less at 500,004 patches and 31 wavelengths).
    const std::size_t nodes = tree_.nodes.size();
    std::vector<uint8_t> below(nodes, 0), sourceSlots(nodes > 0 ? slot_[nodes] : 0, 0);
    for (std::size_t k = nodes; k-- > 0;) {
        const HierarchyNode& node = tree_.nodes[k];
        below[k] = node.isLeaf() ? sources[tree_.order[node.first]]
                                 : below[node.children[0]] | below[node.children[1]];
        sourceSlots[slot_[k]] = below[k];
    }
    std::vector<double> far(n * m);
    farGather(radiosity, m, far, sourceSlots);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t i = range.begin(); i != range.end(); ++i) {
                              if (!receivers[i]) continue;
                              double* g = gathered.data() + i * m;
                              std::fill(g, g + m, 0.0);
                              for (uint64_t e = near_.rowOffsets[i]; e < near_.rowOffsets[i + 1];
                                   ++e) {
                                  const uint32_t j = near_.columns[e];
                                  if (!sources[j]) continue;
                                  const double f = near_.values[e];
                                  const double* b = radiosity.data() + std::size_t(j) * m;
                                  for (std::size_t c = 0; c < m; ++c)
                                      g[c] += f * b[c];
                              }
                              for (std::size_t c = 0; c < m; ++c)
                                  g[c] += far[i * m + c];
                          }
                      });
}

void HierarchicalTransport::row(uint32_t patch, std::vector<TransportEntry>& out) const {
    rowEntries(near_, patch, out);
}

Expected<SolverResult> HierarchicalTransport::solve(const RadiositySystem& system,
                                                    SolverSettings settings) const {
    if (settings.rowSums.empty()) settings.rowSums = rowSums_;
    settings.farGather = [this, m = system.wavelengthCount](std::span<const double> radiosity,
                                                            std::span<double> gathered) {
        farGather(radiosity, m, gathered);
    };
    return solveRadiosity(near_, system, settings);
}

Expected<void> HierarchicalTransport::writeMatrixMarket(const std::string&,
                                                        const std::vector<std::string>&) const {
    return Error{
        "the hierarchical transport holds links, not the matrix F: write F with "
        "--transport matrix"};
}

Expected<MatrixComparison> HierarchicalTransport::compare(const Transport& other,
                                                          const MatrixCompareSettings&) const {
    return Error{concat("cannot compare the hierarchical transport with the ", other.kind(),
                        " transport entry by entry: compare the solutions patch by patch")};
}

namespace {

// A region of the scene from which at most this share of the survey's rays escape is closed:
// the rays that do slip through cracks between faces (3 of 246,784 on the black-light box, 1 of
// 421,888 on the Blender-style box), while any real opening takes far more.
constexpr double kOpenSceneShare = 1e-4;
// A patch more than half of whose survey rays end within this share of its size (the square
// root of its area) is sheltered (cluster_tree.h): something lies on or just over it.
constexpr double kShelter = 0.25;

struct PatchSurvey {
    std::vector<uint8_t> enclosed;  // per patch: kEnclosed, kEnclosedInOpenRegion or 0
    std::vector<uint8_t> lit;  // per patch: in a region with an emitter (light reaches it)
    std::vector<uint8_t> dark;  // per patch: in a region light does not reach (receives none)
    std::vector<uint8_t> sheltered;  // per patch: most of its rays end within kShelter of it
};

// kEnclosureRays cosine-distributed rays from area-uniform points of every patch (one hash per
// ray: independent of the thread count), and what they tell:
// - enclosed: every ray of the patch lands on the front of a patch, none of them a face lying
//   on it (closer than 1% of its size and facing it): closed around it by surfaces that face
//   it, and not partly buried (a patch under a block has no well-defined row sum; the
//   session's exposed parts handle it). In an open region (kEnclosedInOpenRegion) such a patch
//   may still see a small opening all its rays missed (a 3% one is missed by all 32 38% of the
//   time), and its row is filled only when its links already sum to within kOpenFill of 1;
// - lit: the patches of a region (below: patches joined by these rays) with an emitter in it
//   (any patch with emission, punctual lights' reflections included). Light reaches every one
//   of them, also where none of these rays does: a patch whose rays land on a lit patch is seen
//   by it (the floor of a 2 cm gap under a cupboard, which rays from the room rarely enter);
// - dark: the patches of a closed region (above) that is not lit: cavities no light
//   enters, such as the inside of a closed double-sided box standing on the floor, or of a
//   column's shaft closed by its base and capital. They neither send nor receive: no link
//   touches them;
// - sheltered: more than half of the patch's rays end (on any face) within kShelter of its size.
PatchSurvey surveyPatches(const PatchMesh& mesh, const RadiositySystem& system,
                          const RayCaster& caster, uint32_t seed) {
    const std::size_t n = mesh.patchCount(), wavelengths = system.wavelengthCount;
    PatchSurvey survey;
    survey.enclosed.assign(n, 0);
    survey.sheltered.assign(n, 0);
    std::vector<uint32_t> lands(n * kEnclosureRays, kNoPatch);  // front hits only
    std::vector<uint8_t> escaped(n, 0);  // per patch: its rays that hit nothing
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, n, 64),
        [&](const tbb::blocked_range<std::size_t>& range) {
            std::vector<Ray> rays(kEnclosureRays);
            std::vector<uint32_t> hits(kEnclosureRays);
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                const auto& c = mesh.patches[i];
                const shared::vec3 normal = toVec3(mesh.normals[i]);
                for (int k = 0; k < kEnclosureRays; ++k) {
                    const uint32_t h =
                        shared::streamSeed(shared::patchSeed(uint32_t(i), seed), uint32_t(k));
                    const shared::vec3 p = shared::uniformPointOnTriangle(
                        toVec3(mesh.positions[c[0]]), toVec3(mesh.positions[c[1]]),
                        toVec3(mesh.positions[c[2]]),
                        shared::vec2(shared::hashToUnitFloat(0, h), shared::hashToUnitFloat(1, h)));
                    const shared::vec3 d = shared::cosineDirection(
                        normal,
                        shared::vec2((k + shared::hashToUnitFloat(2, h)) / kEnclosureRays,
                                     shared::hashToUnitFloat(3, h)));
                    rays[k] = {{p.x, p.y, p.z}, {d.x, d.y, d.z}};
                }
                caster.closestHits(rays, hits);
                // The distance to each hit, from the hit patch's plane.
                const double contact = 0.01 * std::sqrt(mesh.areas[i]);
                const double shelter = kShelter * std::sqrt(mesh.areas[i]);
                int close = 0;
                bool closed = true;
                for (int k = 0; k < kEnclosureRays; ++k) {
                    if (hits[k] == kNoPatch) {
                        closed = false;
                        ++escaped[i];
                        continue;
                    }
                    const Vec3d o{rays[k].origin[0], rays[k].origin[1], rays[k].origin[2]};
                    const Vec3d d{rays[k].direction[0], rays[k].direction[1], rays[k].direction[2]};
                    // Of a double-sided surface's two coincident faces, the ray meets the one
                    // facing it.
                    uint32_t hit = hits[k];
                    // A flat patch cannot see itself: a ray that meets it or its back face
                    // again (grazing, over an exporter's rounding) tells nothing.
                    if (hit == i || hit == mesh.backPatch[i]) continue;
                    if (dot(mesh.normals[hit], d) >= 0 && mesh.backPatch[hit] != kNoBackPatch)
                        hit = mesh.backPatch[hit];
                    const Vec3d& m = mesh.normals[hit];
                    const double distance =
                        dot(m, mesh.positions[mesh.patches[hit][0]] - o) / dot(m, d);
                    // A back face returns no light; a face lying on this one
                    // (facing it, closer than 1% of its size) buries it.
                    close += distance < shelter;
                    const bool front = dot(m, d) < 0;
                    const bool buried =
                        std::abs(distance) < contact && dot(m, mesh.normals[i]) < -0.99;
                    closed = closed && front && !buried;
                    if (front) lands[i * kEnclosureRays + std::size_t(k)] = hit;
                }
                survey.enclosed[i] = closed ? kEnclosed : 0;
                survey.sheltered[i] = 2 * close > kEnclosureRays;
            }
        });
    // Regions: patches joined by a ray from one landing on the front of the other. In an open
    // one an enclosed patch's row is filled only near 1; a closed one no light reaches is dark.
    // The inside of a closed double-sided room is one region; its walls' outer faces, whose
    // rays all escape, are others, and do not open it.
    DisjointSets regions(n);
    for (std::size_t r = 0; r < lands.size(); ++r) {
        if (lands[r] != kNoPatch) regions.join(uint32_t(r / kEnclosureRays), lands[r]);
    }
    std::vector<uint64_t> regionRays(n, 0), regionEscapes(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const uint32_t root = regions.find(uint32_t(i));
        regionRays[root] += kEnclosureRays;
        regionEscapes[root] += escaped[i];
    }
    std::vector<uint8_t> open(n, 0);  // per region root
    for (std::size_t i = 0; i < n; ++i) {
        const uint32_t root = regions.find(uint32_t(i));
        open[root] = double(regionEscapes[root]) > kOpenSceneShare * double(regionRays[root]);
        if (open[root] && survey.enclosed[i]) survey.enclosed[i] = kEnclosedInOpenRegion;
    }

    // Lit: a region with an emitter. Dark: a closed region that is not lit; its own rays land
    // only inside it, so light from outside has no way in: it receives nothing either. (An
    // open region with no emitter may still see a lamp its few rays missed.)
    std::vector<uint8_t> lit(n, 0);  // per region root
    for (std::size_t i = 0; i < n; ++i) {
        const auto e = system.emission.begin() + std::ptrdiff_t(i * wavelengths);
        if (std::any_of(e, e + std::ptrdiff_t(wavelengths), [](double v) { return v > 0; }))
            lit[regions.find(uint32_t(i))] = 1;
    }
    survey.lit.assign(n, 0);
    survey.dark.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const uint32_t root = regions.find(uint32_t(i));
        survey.lit[i] = lit[root];
        survey.dark[i] = !lit[root] && !open[root];
    }
    return survey;
}

// The tree's arrays, the transport's per-patch ones and a gather's work arrays
// (estimateHierarchy).
uint64_t treeBytes(uint64_t n, std::size_t wavelengthCount) {
    const uint64_t nodes = n > 0 ? 2 * n - 1 : 0;
    return nodes * (sizeof(HierarchyNode) + 8 + sizeof(Vec3d) + 2 * 8) +
        n * (sizeof(Vec3d) + 2 * sizeof(double) + 8) + nodes * 3 * wavelengthCount * (4 + 8);
}

// The build's peak: the tree's arrays beside the link records three times over (each thread's
// grown vector holds up to twice its records, then their merged copy; the records are merged
// and freed one thread at a time, and the far records freed once grouped).
uint64_t buildPeakBytes(uint64_t tree, double farLinks, double nearPairs) {
    return tree + uint64_t(3 * (farLinks * kFarRecordBytes + nearPairs * kNearRecordBytes));
}

}  // namespace

HierarchyEstimate estimateHierarchy(const PatchMesh& mesh, std::size_t wavelengthCount) {
    // Links per patch (docs/performance.md, "Hierarchical transport"): near factors 39, 23, 16
    // and 11 and far links 108, 80, 66 and 54 at 60,024, 120,000, 240,016 and 500,004 patches
    // of the interior generator (they grew to 243 a patch before curved nodes were bounded by
    // their normals' box); near 161, 230, 137, 59 and 60 and far 172, 238, 248, 210 and 376 on
    // the Cornell box, the coloured lights, the default scene, the double-sided and the
    // single-sided Blender-style box. Near factors a patch fall as about n^-0.5 over all of
    // those (finer patches are linked far sooner): at most 1.2 times the coloured lights' on
    // that law (and every patch), at least 0.4 times it (the interiors' are 0.55-0.67 times);
    // far links at most 1.2 times the largest count, 450 a patch, at least 30.
    const uint64_t n = mesh.patchCount();
    const double law = 230 * std::sqrt(3854.0 / std::max<double>(1, double(n)));
    const double most = std::min(double(n), 1.2 * law), least = std::min(double(n), 0.4 * law);
    HierarchyEstimate estimate;
    estimate.nearEntries = static_cast<uint64_t>(double(n) * most);
    estimate.farLinks = static_cast<uint64_t>(double(n) * 450.0);
    const uint64_t tree = treeBytes(n, wavelengthCount);
    // A far half-link (FarHalfLinks) takes 8 bytes between two planar nodes and 16 otherwise,
    // about a fifth of them on the interiors: 12 bytes.
    estimate.bytes = sparseMatrixBytes(n, estimate.nearEntries) + 2 * estimate.farLinks * 12 + tree;
    // About one near pair a near factor. Measured peaks of whole renders: 0.52, 0.91, 1.65 and
    // 3.14 GiB at 60,024, 120,000, 240,016 and 500,004 patches of the interior generator, where
    // the highest rates give 1.16, 2.27, 4.46 and 9.17 GiB and the lowest 0.25, 0.49, 0.96 and
    // 1.95 GiB.
    estimate.peakBytes =
        std::max(estimate.bytes,
                 buildPeakBytes(tree, double(estimate.farLinks), double(estimate.nearEntries)));
    estimate.leastPeakBytes = buildPeakBytes(tree, double(n) * 30.0, double(n) * least);
    return estimate;
}

uint64_t linkRecordLimit(const PatchMesh& mesh, std::size_t wavelengthCount, uint64_t maxBytes) {
    const uint64_t tree = treeBytes(mesh.patchCount(), wavelengthCount);
    return maxBytes <= tree ? 0 : (maxBytes - tree) / 3;
}

Expected<std::shared_ptr<const HierarchicalTransport>> buildHierarchicalTransport(
    const PatchMesh& mesh, const PatchExposure& exposure, const RadiositySystem& system,
    const HierarchySettings& hierarchy, const FormFactorSettings& settings, uint64_t maxBytes) {
    if (settings.method == FormFactorMethod::Stochastic) {
        return Error{
            "--transport hierarchical evaluates its links with the kernels of riemann, "
            "nusselt or hybrid, not stochastic"};
    }
    if (!(hierarchy.linkTolerance > 0) || hierarchy.farRays < 1) {
        return Error{concat("--link-tolerance must be > 0 (got ", hierarchy.linkTolerance, ")")};
    }
    auto caster =
        makeRayCaster(mesh, {.packetMode = PacketMode::Stream, .watertightSegments = true});
    if (!caster) return caster.error();
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    return arena.execute([&]() -> Expected<std::shared_ptr<const HierarchicalTransport>> {
        const PatchSurvey survey =
            surveyPatches(mesh, system, **caster, static_cast<uint32_t>(settings.seed));
        ClusterTree tree = buildClusterTree(mesh, survey.sheltered);
        const std::unique_ptr<PairEvaluator> evaluator =
            makeRayPairEvaluator(mesh, settings, **caster, hierarchy.nearTolerance);
        auto links = buildHierarchicalLinks(
            mesh, tree, exposure, linkImportance(system, survey.lit, survey.dark), hierarchy,
            settings, *evaluator, **caster,
            linkRecordLimit(mesh, system.wavelengthCount, maxBytes));
        if (!links) return links.error();
        return std::make_shared<const HierarchicalTransport>(
            mesh, std::move(tree), std::move(*links), exposure.fraction, survey.enclosed);
    });
}

}  // namespace daisy
