#include "hierarchical/hierarchical_links.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>

#include "core/cancel.h"
#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "geometry/shared_vec.h"
#include "shared/formfactor.h"
#include "shared/rng.h"
#include "shared/sampling.h"

namespace daisy {
namespace {

// Candidate pairs the breadth-first expansion gathers before the depth-first refinement runs
// them in parallel (each one's subtree of decisions is independent of the others').
constexpr std::size_t kParallelFrontier = 4096;
// Shadow segments are trimmed by this share of their length at each end, so the patches they
// start and end on (and their neighbours at a shared edge) do not block them.
constexpr float kSegmentTrim = 1e-4f;

// A far link as the refinement finds it: K (coupling >= 0), or for a planar pair whose weight
// was estimated from its segments (Refiner::far), minus that weight.
struct FarRecord {
    uint32_t receiver, source;
    float coupling;
};
static_assert(sizeof(FarRecord) == kFarRecordBytes &&
              sizeof(shared::PairIndex) == kNearRecordBytes);
// Each thread adds its records to the build's count in steps of this many bytes.
constexpr uint64_t kRecordCountStep = 64 * 1024;
// Centroid cosine products at or under this take the segments' estimate (Refiner::far).
constexpr double kCosineFloor = 1e-6;
// Mixed into a pair's seed for its roulette draw (Refiner::far), apart from its segments'.
constexpr uint32_t kRouletteSalt = 0x5bd1e995u;

// The mean of cos_x cos_y / r^2 over area-uniform points x of R and y of S, relative to its
// value at the centroids, to second order in the offsets s = (y - x) - d u (E[s] = 0, covariance
// C, the sum of the two nodes'): for f(w) = (a.w)(b.w) / |w|^4, a = n_R, b = -n_S,
//   E f / f(d u) = 1 + (a.Cb - 4 (beta u.Ca + alpha u.Cb) - 2 alpha beta tr C
//                       + 12 alpha beta u.Cu) / (alpha beta d^2),
// alpha = a.u, beta = b.u (the Hessian of f at d u). Facing along u (a = b = u) it is
// 1 + (5 u.Cu - 2 tr C) / d^2: parallel plates 4 apart, a unit and a 0.5 square, give
// 1 - 2 (1/6 + 1/24) / 16. A node that is not planar has no one normal: the facing form then.
double secondOrder(const HierarchyNode& r, const HierarchyNode& s, const Vec3d& u, double d) {
    double c[6];
    for (int k = 0; k < 6; ++k)
        c[k] = r.spread[k] + s.spread[k];
    const auto times = [&c](const Vec3d& v) {
        return Vec3d{c[0] * v.x + c[3] * v.y + c[4] * v.z, c[3] * v.x + c[1] * v.y + c[5] * v.z,
                     c[4] * v.x + c[5] * v.y + c[2] * v.z};
    };
    const double trace = c[0] + c[1] + c[2];
    const Vec3d cu = times(u);
    const Vec3d a = r.isPlanar() ? r.coneAxis : u;
    const Vec3d b = s.isPlanar() ? s.coneAxis * -1.0 : u;
    const double alpha = dot(a, u), beta = dot(b, u);
    const double term = dot(a, times(b)) - 4 * (beta * dot(cu, a) + alpha * dot(cu, b)) -
        2 * alpha * beta * trace + 12 * alpha * beta * dot(u, cu);
    return std::clamp(1 + term / (alpha * beta * d * d), 0.5, 1.5);
}

struct Pair {
    uint32_t r, s;
};

// What each worker thread collects.
struct Local {
    std::vector<FarRecord> far;
    std::vector<shared::PairIndex> near;
    LinkStats stats;
    SegmentArrays segments;
    std::vector<uint8_t> blocked;
    uint64_t countedBytes = 0;  // of far and near, what the build's count has seen

    uint64_t recordBytes() const {
        return far.size() * kFarRecordBytes + near.size() * kNearRecordBytes;
    }
};

class Refiner {
public:
    Refiner(const PatchMesh& mesh, const ClusterTree& tree, const PatchExposure& exposure,
            const LinkImportance& importance, const HierarchySettings& hierarchy,
            const FormFactorSettings& settings, const RayCaster& rays)
        : tree_(tree),
          hierarchy_(hierarchy),
          rays_(rays),
          seed_(static_cast<uint32_t>(settings.seed ^ (settings.seed >> 32))) {
        const std::size_t nodes = tree.nodes.size();
        source_.assign(nodes, 0.0);
        yield_.assign(nodes, 0.0);
        for (std::size_t k = nodes; k-- > 0;) {
            const HierarchyNode& node = tree.nodes[k];
            if (node.isLeaf()) {
                const uint32_t patch = tree.order[node.first];
                source_[k] = importance.source[patch];
                yield_[k] = importance.yield[patch];
            } else {
                source_[k] = std::max(source_[node.children[0]], source_[node.children[1]]);
                yield_[k] = std::max(yield_[node.children[0]], yield_[node.children[1]]);
            }
        }
        epsilon_ = hierarchy.linkTolerance * importance.totalPower;
        visibilityEpsilon_ = hierarchy.visibilityShare * epsilon_;
        prefixExposed_.resize(tree.order.size() + 1, 0.0);
        corners_.resize(tree.order.size());
        exposedPoints_.resize(tree.order.size());
        for (std::size_t k = 0; k < tree.order.size(); ++k) {
            const uint32_t patch = tree.order[k];
            prefixExposed_[k + 1] =
                prefixExposed_[k] + mesh.areas[patch] * exposure.fraction[patch];
            exposedPoints_[k] = exposure.exposedPoints[patch];
            for (int c = 0; c < 3; ++c)
                corners_[k][c] = toVec3(mesh.positions[mesh.patches[patch][c]]);
        }
    }

    // Decides one pair: a link (far or near), nothing, or up to three child pairs in `next`.
    void decide(Pair pair, Local& local, std::vector<Pair>& next) const {
        ++local.stats.candidates;
        const HierarchyNode& r = tree_.nodes[pair.r];
        const HierarchyNode& s = tree_.nodes[pair.s];
        if (pair.r == pair.s) {
            if (r.isLeaf()) return;  // a flat patch does not see itself
            const uint32_t a = r.children[0], b = r.children[1];
            next.push_back({a, a});
            next.push_back({b, b});
            next.push_back({a, b});
            return;
        }
        const LinkDecision decision =
            chooseLink(r, s, {source_[pair.r], yield_[pair.r], source_[pair.s], yield_[pair.s]},
                       epsilon_, hierarchy_.maxAperture);
        LinkChoice choice = decision.choice;
        if (choice == LinkChoice::None) {
            ++local.stats.facingAway;
            return;
        }
        if (choice == LinkChoice::Far) {
            if (far(pair, decision.power, local)) return;
            choice = splitChoice(r, s);  // partly visible: refine
        }
        if (choice == LinkChoice::Near) {
            local.near.push_back({std::min(tree_.order[r.first], tree_.order[s.first]),
                                  std::max(tree_.order[r.first], tree_.order[s.first])});
            return;
        }
        const bool splitR = choice == LinkChoice::SplitReceiver;
        for (uint32_t child : (splitR ? r : s).children)
            next.push_back(splitR ? Pair{child, pair.s} : Pair{pair.r, child});
    }

private:
    // The far link of a pair that passed the geometric tests: its visibility, then the link,
    // nothing (hidden), or false (partly visible and worth refining).
    bool far(Pair pair, double phi, Local& local) const {
        const HierarchyNode& r = tree_.nodes[pair.r];
        const HierarchyNode& s = tree_.nodes[pair.s];
        // The segments start and end on the exposed parts (a buried point, inside a closed
        // object, sees nothing), and V is the exposed parts' visibility: the gather weighs each
        // patch by its exposed share (hierarchical_transport.h). Sampled over the whole nodes,
        // a patch half under a poster would look partly visible from everywhere and be refined
        // down to single patches, each pair another chance for all its segments to start under
        // the poster and the pair to be dropped as hidden (the rows of the black-light box's wall
        // patches under its posters' edges were 0.44-1.33 of the matrix path's).
        if (!(exposedArea(r) > 0 && exposedArea(s) > 0)) {
            ++local.stats.hidden;
            return true;
        }
        // A pair that may be refined is shot at in two batches of farRays / 2 segments, each
        // stratified over both nodes: the first decides (partly blocked: refine), the second,
        // independent of that decision, estimates V. Estimated from the rays that decided it, V
        // would be biased: a partly visible pair kept only when all its segments got through
        // (as V = 1), dropped only when none did. A link whose partial visibility would not be
        // refined needs only an unbiased V, not a precise one: farRays / 4 segments, or one
        // (farRays / 8) when its bound Phi is within the visibility share of epsilon, so that
        // its V noise (a standard deviation of at most half its estimate, at most 0.75 Phi, on
        // one segment) stays within that share. Those links are most of a large scene's, and
        // their noise averages out over a receiver's hundreds of links: by its counts of pairs
        // and segments, the 250,002-triangle interior shot about 442 M of its 553 M segments
        // at the about 221 M pairs not refined for visibility, two each (332 M segments in
        // all with one for those within the share). One segment and two gave the same error
        // against the path tracer on the black-light box (2.42%) and the 30,012-triangle
        // interior (7.03% and 7.04%); one for every link under the threshold failed
        // HalfOccludedSquaresShareExactlyHalf's coarse case (8.5% off with 88 links).
        const uint32_t seed = shared::pairSeed(pair.r, pair.s, seed_);
        // A pair within the visibility share is kept by Russian roulette, with probability
        // q = Phi / (share epsilon) drawn from its own hash, and then carries its estimate over
        // q. The expected transport is unchanged, and a kept link's estimate stays within what
        // a link at the share carries, so its noise is bounded as the others' under the
        // threshold. Such pairs were most of the large interior's: at 250,002 triangles 66.7 M
        // of the 98 M pairs shot at, 49.3 M of them hidden, a segment each besides the oracle's
        // and the sampling's work; the roulette left 12.6 M far links instead of 27.1 M and
        // 149 M segments instead of 211 M (docs/hierarchical.md, "Visibility").
        double keptScale = 1;
        if (phi <= visibilityEpsilon_) {
            const double q = visibilityEpsilon_ > 0 ? phi / visibilityEpsilon_ : 0.0;
            if (!(double(shared::uintToUnitFloat(shared::pcgHash(seed ^ kRouletteSalt))) < q)) {
                ++local.stats.rouletteDropped;
                return true;
            }
            keptScale = 1 / q;
        }
        const bool refinable = 0.5 * phi > visibilityEpsilon_;
        const int batches = refinable ? 2 : 1;
        const int size =
            std::max(1, hierarchy_.farRays / (refinable ? 2 : (phi > visibilityEpsilon_ ? 4 : 8)));
        int open = 0;
        for (int batch = 0; batch < batches; ++batch) {
            local.segments.resize(std::size_t(size));
            local.blocked.assign(std::size_t(size), 0);
            for (int k = 0; k < size; ++k) {
                const uint32_t stream = 2 * uint32_t(batch * size + k);
                const shared::vec3 x = samplePoint(r, k, size, shared::streamSeed(seed, stream));
                const shared::vec3 y =
                    samplePoint(s, (k * 5 + 3) % size, size, shared::streamSeed(seed, stream + 1));
                const shared::vec3 a = x + (y - x) * kSegmentTrim;
                const shared::vec3 b = y + (x - y) * kSegmentTrim;
                local.segments.set(std::size_t(k), a.x, a.y, a.z, b.x, b.y, b.z);
            }
            rays_.occluded(local.segments, local.blocked);
            local.stats.raysCast += uint64_t(size);
            open = 0;
            for (uint8_t b : local.blocked)
                open += b == 0;
            if (batch + 1 < batches && open > 0 && open < size) {
                ++local.stats.partlyVisibleRefined;
                return false;
            }
        }
        if (open == 0) {
            ++local.stats.hidden;
            return true;
        }
        const double distance = length(s.centroid - r.centroid);
        const Vec3d u = farDirection(r.centroid, s.centroid);
        // Two planar nodes past the far field's aperture, or whose centroids' direction lies
        // behind a side (pairs the oracle links because their whole exchange is within
        // epsilon): the point-to-point form at the centroids, biased low there (or nothing),
        // gives way to the mean of the segments' own kernel (shared::riemannKernel, V cos cos /
        // (pi r^2)) over area-uniform points of the exposed parts (unbiased), as the link's
        // weight. Like K's it lies within [0, C] (r >= d - rho, capped below), so the oracle's
        // bound holds.
        const double cosines = dot(r.coneAxis, u) * -dot(s.coneAxis, u);
        if (r.isPlanar() && s.isPlanar() &&
            (cosines <= kCosineFloor ||
             r.radius + s.radius > hierarchy_.maxAperture * length(s.center - r.center))) {
            const shared::vec3 nr = toVec3(r.coneAxis), ns = toVec3(s.coneAxis);
            const SegmentArrays& g = local.segments;
            double sum = 0;
            for (int k = 0; k < size; ++k) {
                if (local.blocked[std::size_t(k)]) continue;
                sum += shared::riemannKernel(shared::vec3(g.x0[k], g.y0[k], g.z0[k]), nr,
                                             shared::vec3(g.x1[k], g.y1[k], g.z1[k]), ns);
            }
            // Capped as K below: weight <= K for cosines up to 1 (then over the roulette's q).
            const double weight = keptScale * std::min(sum / size, 1 / std::max(r.area, s.area));
            if (weight > 0) {
                local.far.push_back({pair.r, pair.s, float(-weight)});
            } else {
                ++local.stats.hidden;
            }
            return true;
        }
        // Capped so that neither side's factor F = K cos cos A can pass 1 (kFarEstimateBound):
        // a pair linked at a wide aperture may have its centroids close together.
        const double coupling = keptScale *
            std::min(double(open) / size * secondOrder(r, s, u, distance) /
                         (M_PI * distance * distance),
                     1 / std::max(r.area, s.area));
        local.far.push_back({pair.r, pair.s, float(coupling)});
        return true;
    }

    // The node's exposed area (radiosity/patch_exposure.h).
    double exposedArea(const HierarchyNode& node) const {
        return prefixExposed_[node.first + node.count] - prefixExposed_[node.first];
    }

    // Point k of `count` on node `node`'s exposed part, area-uniform: the patch by stratified
    // exposed area, then a uniform point on it, or on one of its exposed children when part of
    // it is buried (shared/sampling.h, radiosity/patch_exposure.h).
    shared::vec3 samplePoint(const HierarchyNode& node, int k, int count, uint32_t seed) const {
        // shared::hashToUnitFloat(i, seed), its hash of the seed made once.
        const uint32_t hashed = shared::pcgHash(seed);
        const auto unit = [hashed](uint32_t i) {
            return shared::uintToUnitFloat(shared::pcgHash(i ^ hashed));
        };
        std::size_t index = node.first;
        if (!node.isLeaf()) {
            const double lo = prefixExposed_[node.first];
            const double hi = prefixExposed_[node.first + node.count];
            const double target = lo + (hi - lo) * ((k + unit(0)) / count);
            auto it = std::upper_bound(prefixExposed_.begin() + node.first + 1,
                                       prefixExposed_.begin() + node.first + node.count, target);
            index = static_cast<std::size_t>(it - prefixExposed_.begin()) - 1;
        }
        const std::array<shared::vec3, 3>& c = corners_[index];
        const shared::vec2 u(unit(1), unit(2));
        const unsigned exposed = exposedPoints_[index];
        const int points = std::popcount(exposed);
        if (points == kPatchQuadraturePoints || points == 0) {
            return shared::uniformPointOnTriangle(c[0], c[1], c[2], u);
        }
        // The j-th exposed child, j uniform.
        unsigned rest = exposed;
        for (int j = std::min(points - 1, int(unit(3) * points)); j > 0; --j)
            rest &= rest - 1;
        return pointInPatchChild(c[0], c[1], c[2], std::countr_zero(rest), u);
    }

    const ClusterTree& tree_;
    const HierarchySettings& hierarchy_;
    const RayCaster& rays_;
    uint32_t seed_;
    std::vector<double> source_, yield_;  // per node: largest source and yield
    std::vector<double> prefixExposed_;  // exposed area over tree.order
    std::vector<std::array<shared::vec3, 3>> corners_;  // each patch's corners, in tree.order
    std::vector<uint16_t> exposedPoints_;  // each patch's exposed children, in tree.order
    double epsilon_ = 0;
    double visibilityEpsilon_ = 0;
};

void addStats(LinkStats& into, const LinkStats& from) {
    into.candidates += from.candidates;
    into.facingAway += from.facingAway;
    into.hidden += from.hidden;
    into.partlyVisibleRefined += from.partlyVisibleRefined;
    into.rouletteDropped += from.rouletteDropped;
    into.raysCast += from.raysCast;
}

// The records' half-links grouped by receiver, sources ascending, each record giving one to
// each side, in the form the gather applies them (FarHalfLinks).
FarHalfLinks groupFarLinks(const std::vector<FarRecord>& records, const ClusterTree& tree,
                           const std::vector<Vec3d>& normals) {
    const std::size_t nodes = tree.nodes.size();
    const std::vector<Vec3d> orientation = gatherOrientations(tree, normals);
    const std::vector<uint64_t> slots = gatherSlots(orientation);
    const auto planar = [&orientation](uint32_t k) { return orientation[k] != Vec3d{}; };
    FarHalfLinks far;
    far.planarOffsets.assign(nodes + 1, 0);
    far.otherOffsets.assign(nodes + 1, 0);
    for (const FarRecord& record : records) {
        std::vector<uint64_t>& offsets =
            planar(record.receiver) && planar(record.source) ? far.planarOffsets : far.otherOffsets;
        ++offsets[record.receiver + 1];
        ++offsets[record.source + 1];
    }
    for (std::size_t k = 0; k < nodes; ++k) {
        far.planarOffsets[k + 1] += far.planarOffsets[k];
        far.otherOffsets[k + 1] += far.otherOffsets[k];
    }
    far.planarSlots.resize(far.planarOffsets[nodes]);
    far.planarWeights.resize(far.planarOffsets[nodes]);
    far.others.resize(far.otherOffsets[nodes]);
    std::vector<uint64_t> planarCursor(far.planarOffsets.begin(), far.planarOffsets.end() - 1);
    std::vector<uint64_t> otherCursor(far.otherOffsets.begin(), far.otherOffsets.end() - 1);
    const auto add = [&](uint32_t r, uint32_t s, double coupling) {
        const Vec3d u = farDirection(tree.nodes[r].centroid, tree.nodes[s].centroid);
        const uint32_t slot = uint32_t(slots[s]);
        if (planar(r) && planar(s)) {
            const uint64_t e = planarCursor[r]++;
            far.planarSlots[e] = slot;
            far.planarWeights[e] = coupling < 0  // the weight itself (FarRecord)
                ? float(-coupling)
                : float(-coupling * dot(u, orientation[s]) * dot(u, orientation[r]));
            return;
        }
        Vec3d v;
        if (planar(s)) {
            v = u * (-coupling * dot(u, orientation[s]));
        } else if (planar(r)) {
            v = u * (-coupling * dot(u, orientation[r]));
        } else {
            v = u * std::sqrt(coupling);
        }
        far.others[otherCursor[r]++] = {planar(s) ? slot | FarHalfLinks::kPlanarSource : slot,
                                        {float(v.x), float(v.y), float(v.z)}};
    };
    for (const FarRecord& record : records) {
        add(record.receiver, record.source, record.coupling);
        add(record.source, record.receiver, record.coupling);
    }
    // Sources ascending under each receiver (slots ascend with the node index): the order
    // the threads' records came in does not show.
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, nodes, 1024),
        [&](const tbb::blocked_range<std::size_t>& range) {
            std::vector<std::pair<uint32_t, float>> planarRow;
            for (std::size_t k = range.begin(); k != range.end(); ++k) {
                const uint64_t begin = far.planarOffsets[k];
                const uint64_t end = far.planarOffsets[k + 1];
                planarRow.clear();
                for (uint64_t e = begin; e < end; ++e)
                    planarRow.emplace_back(far.planarSlots[e], far.planarWeights[e]);
                std::sort(planarRow.begin(), planarRow.end());
                for (uint64_t e = begin; e < end; ++e) {
                    far.planarSlots[e] = planarRow[e - begin].first;
                    far.planarWeights[e] = planarRow[e - begin].second;
                }
                std::sort(far.others.begin() + std::ptrdiff_t(far.otherOffsets[k]),
                          far.others.begin() + std::ptrdiff_t(far.otherOffsets[k + 1]),
                          [](const FarHalfLinks::OtherLink& a, const FarHalfLinks::OtherLink& b) {
                              return a.source() < b.source();
                          });
            }
        });
    return far;
}

// The near links' factors, both directions, as F's rows (zeros dropped).
Expected<SparseMatrix> evaluateNear(const std::vector<shared::PairIndex>& pairs, uint32_t n,
                                    const FormFactorSettings& settings, PairEvaluator& evaluator) {
    std::vector<shared::PairFactors> factors(pairs.size());
    const std::size_t batch = std::max<std::size_t>(1, evaluator.batchPairs());
    {
        Progress progress("near factors", pairs.size(), "pairs",
                          settings.progress && progressEnabledByDefault(), settings.onProgress);
        for (std::size_t begin = 0; begin < pairs.size(); begin += batch) {
            if (isCancelled(settings.cancel)) return Error{kInterruptedMessage};
            const std::size_t count = std::min(batch, pairs.size() - begin);
            auto done = evaluator.evaluate({pairs.data() + begin, count}, settings.raysPerPair,
                                           {factors.data() + begin, count});
            if (!done) return done.error();
            progress.advance(count);
        }
    }
    SparseMatrix matrix = SparseMatrix::zeros(n);
    std::vector<uint64_t>& offsets = matrix.rowOffsets;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (factors[k].fij != 0) ++offsets[pairs[k].i + 1];
        if (factors[k].fji != 0) ++offsets[pairs[k].j + 1];
    }
    for (uint32_t i = 0; i < n; ++i)
        offsets[i + 1] += offsets[i];
    matrix.columns.resize(offsets.back());
    matrix.values.resize(offsets.back());
    std::vector<uint64_t> cursor(offsets.begin(), offsets.end() - 1);
    // Both directions of the pairs interleave in a row: each row is sorted by column after.
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const auto [i, j] = pairs[k];
        if (factors[k].fij != 0) {
            matrix.columns[cursor[i]] = j, matrix.values[cursor[i]++] = factors[k].fij;
        }
        if (factors[k].fji != 0) {
            matrix.columns[cursor[j]] = i, matrix.values[cursor[j]++] = factors[k].fji;
        }
    }
    tbb::parallel_for(uint32_t(0), n, [&](uint32_t i) {
        const uint64_t begin = offsets[i], end = offsets[i + 1];
        std::vector<std::pair<uint32_t, float>> row(end - begin);
        for (uint64_t e = begin; e < end; ++e)
            row[e - begin] = {matrix.columns[e], matrix.values[e]};
        std::sort(row.begin(), row.end());
        for (uint64_t e = begin; e < end; ++e)
            matrix.columns[e] = row[e - begin].first, matrix.values[e] = row[e - begin].second;
    });
    return matrix;
}

}  // namespace

uint64_t FarHalfLinks::bytes() const {
    return (planarOffsets.size() + otherOffsets.size()) * sizeof(uint64_t) +
        planarSlots.size() * sizeof(uint32_t) + planarWeights.size() * sizeof(float) +
        others.size() * sizeof(OtherLink);
}

std::vector<Vec3d> gatherOrientations(const ClusterTree& tree, const std::vector<Vec3d>& normals) {
    std::vector<Vec3d> orientation(tree.nodes.size(), Vec3d{});
    for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
        const HierarchyNode& node = tree.nodes[k];
        if (node.isLeaf()) {
            orientation[k] = normals[tree.order[node.first]];
        } else if (node.isPlanar()) {
            orientation[k] = node.coneAxis;
        }
    }
    return orientation;
}

std::vector<uint64_t> gatherSlots(const std::vector<Vec3d>& orientations) {
    std::vector<uint64_t> slots(orientations.size() + 1, 0);
    for (std::size_t k = 0; k < orientations.size(); ++k)
        slots[k + 1] = slots[k] + (orientations[k] != Vec3d{} ? 1 : 3);
    return slots;
}

Expected<HierarchicalLinks> buildHierarchicalLinks(const PatchMesh& mesh, const ClusterTree& tree,
                                                   const PatchExposure& exposure,
                                                   const LinkImportance& importance,
                                                   const HierarchySettings& hierarchy,
                                                   const FormFactorSettings& settings,
                                                   PairEvaluator& evaluator, const RayCaster& rays,
                                                   uint64_t recordLimitBytes) {
    HierarchicalLinks links;
    const auto n = static_cast<uint32_t>(mesh.patchCount());
    if (n == 0) {
        links.near = SparseMatrix::zeros(0);
        links.far.planarOffsets.assign(1, 0);
        links.far.otherOffsets.assign(1, 0);
        return links;
    }
    Timer timer;
    const Refiner refiner(mesh, tree, exposure, importance, hierarchy, settings, rays);
    tbb::enumerable_thread_specific<Local> locals;

    // Breadth first until there is enough parallel work, then each pair's subtree depth first.
    std::vector<Pair> frontier{{0, 0}}, next;
    Local& first = locals.local();
    while (!frontier.empty() && frontier.size() < kParallelFrontier) {
        next.clear();
        for (const Pair& pair : frontier)
            refiner.decide(pair, first, next);
        frontier.swap(next);
    }
    std::atomic<bool> cancelled{false}, overLimit{first.recordBytes() > recordLimitBytes};
    // The records made so far by all threads, each adding its own in kRecordCountStep steps.
    std::atomic<uint64_t> recorded{first.recordBytes()};
    first.countedBytes = recorded;
    const auto count = [&](Local& local) {
        const uint64_t added = local.recordBytes() - local.countedBytes;
        if (added < kRecordCountStep) return;
        if (recorded.fetch_add(added) + added > recordLimitBytes) overLimit = true;
        local.countedBytes += added;
    };
    {
        // The frontier's pairs as the unit of work: their subtrees differ in size, so the
        // fraction is a rough one.
        Progress progress("links", frontier.size(), "node pairs",
                          settings.progress && progressEnabledByDefault(), settings.onProgress);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, frontier.size(), 16),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              Local& local = locals.local();
                              std::vector<Pair> stack;
                              for (std::size_t k = range.begin(); k != range.end(); ++k) {
                                  if (isCancelled(settings.cancel)) {
                                      cancelled = true;
                                      return;
                                  }
                                  stack.assign(1, frontier[k]);
                                  while (!stack.empty() && !overLimit) {
                                      const Pair pair = stack.back();
                                      stack.pop_back();
                                      refiner.decide(pair, local, stack);
                                      count(local);
                                  }
                                  if (overLimit) return;
                              }
                              progress.advance(range.size());
                          });
    }
    if (cancelled) return Error{kInterruptedMessage};
    // The threads' last steps, under kRecordCountStep, were not counted: the limit holds exactly.
    uint64_t farCount = 0, nearCount = 0;
    for (const Local& local : locals) {
        farCount += local.far.size();
        nearCount += local.near.size();
    }
    if (overLimit || farCount * kFarRecordBytes + nearCount * kNearRecordBytes > recordLimitBytes) {
        return Error{concat(kLinkRecordsOverLimit, formatBytes(double(recordLimitBytes)), " at ",
                            formatCount(farCount), " far links and ", formatCount(nearCount),
                            " near pairs")};
    }

    // Each thread's records are merged and freed one thread at a time, and the far records are
    // freed once grouped, so that no more than one extra copy of either is ever held (the peak
    // that estimateHierarchy charges).
    std::vector<FarRecord> far;
    std::vector<shared::PairIndex> near;
    far.reserve(farCount);
    near.reserve(nearCount);
    for (Local& local : locals) {
        addStats(links.stats, local.stats);
        far.insert(far.end(), local.far.begin(), local.far.end());
        near.insert(near.end(), local.near.begin(), local.near.end());
        std::vector<FarRecord>().swap(local.far);
        std::vector<shared::PairIndex>().swap(local.near);
    }
    links.stats.farLinks = far.size();
    links.far = groupFarLinks(far, tree, mesh.normals);
    std::vector<FarRecord>().swap(far);
    tbb::parallel_sort(near.begin(), near.end(),
                       [](const shared::PairIndex& a, const shared::PairIndex& b) {
                           return a.i < b.i || (a.i == b.i && a.j < b.j);
                       });
    links.stats.refineSeconds = timer.seconds();

    Timer nearTimer;
    links.stats.nearPairsEvaluated = near.size();
    auto matrix = evaluateNear(near, n, settings, evaluator);
    if (!matrix) return matrix.error();
    links.near = std::move(*matrix);
    links.stats.nearEntries = links.near.nonzeroCount();
    links.stats.nearSeconds = nearTimer.seconds();
    return links;
}

}  // namespace daisy
