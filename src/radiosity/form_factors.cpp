// The one form-factor driver of every pair backend (DESIGN.md section 3): one class with its
// culling, cost model and storage, about 700 lines because they share its state; the backends
// only evaluate batches of pairs (radiosity/pair_evaluator.h). The stochastic method is in
// stochastic_form_factors.cpp.
#include "radiosity/form_factors.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "core/memory.h"
#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "radiosity/blocker_bvh.h"
#include "radiosity/form_factors_internal.h"
#include "radiosity/patch_clusters.h"
#include "radiosity/ray_pair_evaluator.h"
#include "radiosity/shaft.h"
#include "shared/config.h"
#include "shared/formfactor.h"
#include "shared/rng.h"
#include "shared/sampling.h"
#include "shared/visibility.h"

namespace daisy {
namespace detail {

using shared::PatchGeometry;
using shared::vec3;

int methodConstant(FormFactorMethod method) {
    switch (method) {
        case FormFactorMethod::Riemann:
            return DAISY_METHOD_RIEMANN;
        case FormFactorMethod::Nusselt:
            return DAISY_METHOD_NUSSELT;
        case FormFactorMethod::Stochastic:
            return DAISY_METHOD_STOCHASTIC;
        case FormFactorMethod::Hybrid:
            return DAISY_METHOD_HYBRID;
    }
    return DAISY_METHOD_HYBRID;
}

uint32_t seed32(uint64_t seed) {
    return shared::pcgHash(static_cast<uint32_t>(seed) ^
                           shared::pcgHash(static_cast<uint32_t>(seed >> 32)));
}

std::vector<PatchGeometry> kernelGeometry(const PatchMesh& mesh) {
    const auto toVec3 = [](const Vec3d& v) {
        return vec3(static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z));
    };
    std::vector<PatchGeometry> geometry(mesh.patchCount());
    for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
        PatchGeometry& g = geometry[p];
        g = shared::makePatchGeometry(toVec3(mesh.positions[mesh.patches[p][0]]),
                                      toVec3(mesh.positions[mesh.patches[p][1]]),
                                      toVec3(mesh.positions[mesh.patches[p][2]]));
        g.normal = toVec3(mesh.normals[p]);
        g.area = static_cast<float>(mesh.areas[p]);
    }
    return geometry;
}

}  // namespace detail

namespace {

using detail::computeStochastic;
using detail::kernelGeometry;
using shared::PairIndex;
using shared::PatchGeometry;
using shared::vec3;

// Shafts treat points within this fraction of the size of what they are built from (the two
// outlines' bounding box) as on a plane, plus kRoundingRelative of those coordinates' magnitude
// (a few float roundings of where they are): relative to the patches involved, never to the
// scene, so one far triangle changes no nearby decision (issue 18).
constexpr double kShaftToleranceRelative = 1e-6;
constexpr double kRoundingRelative = 2.5e-7;
// Consecutive clusters are grouped into row blocks of at least this many rows, one task each.
// Each block keeps a column table of n uint32 (where its rows' mirrored entries start in every
// lower row), so the tables cost n^2 / 8 bytes in all, about 1/40 of the matrix.
constexpr uint32_t kMinRowBlockRows = 32;
// Node pairs with at most this many patch pairs are traced rather than refined.
constexpr uint64_t kMinRefinePairs = 4;
// Row blocks are classified in waves of about this many candidate pairs, whose pairs are then
// evaluated in the backend's batches: the pending lists are bounded by the wave, not the scene.
constexpr uint64_t kWavePairs = uint64_t(1) << 20;
// The cost model refines a node pair only while its shafts cost less than this fraction of
// tracing its pairs: a split resolves only part of its pairs (most small shafts are truly
// partly blocked), so it must be clearly cheaper to pay.
constexpr double kRefineBenefit = 0.5;
// Node pairs of at most kSmallNodePairs patch pairs are refined only when their shafts cost under
// kSmallRefineBenefit of tracing them: the last splits mostly leave partly blocked leaves. On the
// cpu backend this stops at 16 pairs (the pair loop 10-20% faster on every scene of the family
// and the Blender Cornell box than refining down to 4, with a quarter more rays); a backend whose
// rays are dear (vulkan on lavapipe) still refines to 4 (docs/performance.md, issue 18 session 4).
constexpr uint64_t kSmallNodePairs = 16;
constexpr double kSmallRefineBenefit = 0.125;
// With the gate closed (culling has cost more than its rays saved), one cluster pair in this
// many is still culled, so the gate can open again where culling starts to pay.
constexpr std::size_t kGateSample = 8;

// Candidate pairs (i < j, not facing away), one bit each; every row starts on a word boundary
// so rows can be filled in parallel.
struct CandidateBitmap {
    std::vector<uint64_t> rowWord;  // n + 1
    std::vector<uint64_t> words;

    explicit CandidateBitmap(uint32_t n) : rowWord(std::size_t(n) + 1, 0) {
        for (uint32_t i = 0; i < n; ++i)
            rowWord[i + 1] = rowWord[i] + (uint64_t(n - 1 - i) + 63) / 64;
    }
    static uint64_t bytes(uint64_t n) { return 8 * (n * n / 128 + 2 * n + 1); }
    void allocate() { words.assign(rowWord.back(), 0); }
    bool test(uint32_t i, uint32_t j) const {
        const uint64_t bit = j - i - 1;
        return (words[rowWord[i] + bit / 64] >> (bit % 64)) & 1;
    }
    void set(uint32_t i, uint32_t j) {
        const uint64_t bit = j - i - 1;
        words[rowWord[i] + bit / 64] |= uint64_t(1) << (bit % 64);
    }
    // Sets the bits of (i, j) for every j in [first, end), first > i.
    void setRange(uint32_t i, uint32_t first, uint32_t end) {
        for (uint64_t bit = first - i - 1, stop = end - i - 1; bit < stop;) {
            const uint64_t shift = bit % 64;
            const uint64_t take = std::min<uint64_t>(64 - shift, stop - bit);
            const uint64_t mask = take == 64 ? ~uint64_t(0) : ((uint64_t(1) << take) - 1) << shift;
            words[rowWord[i] + bit / 64] |= mask;
            bit += take;
        }
    }
};

void addStats(FormFactorStats& total, const FormFactorStats& part) {
    total.facingAway += part.facingAway;
    total.zeroFactor += part.zeroFactor;
    total.clearClusterShafts += part.clearClusterShafts;
    total.clearPairShafts += part.clearPairShafts;
    total.coveredPairs += part.coveredPairs;
    total.tracedPairs += part.tracedPairs;
    total.hiddenPairs += part.hiddenPairs;
    total.raysCast += part.raysCast;
    total.shaftsBuilt += part.shaftsBuilt;
    total.culledClusterPairs += part.culledClusterPairs;
    total.costTracedClusterPairs += part.costTracedClusterPairs;
    total.costStoppedRefinements += part.costStoppedRefinements;
}

// What shaft culling decided for a pair of a cluster pair.
enum class Visibility : uint8_t {
    Trace,  // cast the K rays
    ClearCluster,  // V = 1: the cluster pair's shaft is empty
    ClearRefined,  // V = 1: a smaller shaft around the pair is empty
    Covered,  // V = 0: a solid face crosses the whole shaft
};

// A pair waiting for the backend: where its two entries go.
struct PendingPair {
    uint64_t slot;  // of F_ij
    uint64_t mirrorSlot;  // of F_ji
    uint32_t i, j;
};

// What one row block hands to the evaluation: its pairs by kind, and its counts.
struct BlockOutput {
    std::vector<PendingPair> clear;  // V = 1: the unoccluded factor
    std::vector<PendingPair> trace;  // the K rays
    FormFactorStats stats;
    uint64_t pairs = 0;  // unordered pairs of the block, for progress
    double cullSeconds = 0;  // spent culling (thread seconds)
    double cullPredicted = 0;  // what the calibrated model predicted for that work
    // Empties the output for another block, keeping the lists' storage: a wave's lists are
    // hundreds of MB in all, and fresh storage each wave cost its page faults again.
    void reset() {
        clear.clear();
        trace.clear();
        stats = {};
        pairs = 0;
        cullSeconds = 0;
        cullPredicted = 0;
    }
};

// One wave's evaluation, for the ray cost's correction: thread seconds of the clear and the
// traced batches, the clear pairs, and the traced pairs' rays and open pairs (some ray through).
struct WaveEvaluation {
    double clearSeconds = 0, tracedSeconds = 0;
    uint64_t clearPairs = 0, rays = 0, openTraced = 0;
};

struct ThreadScratch {
    // One shaft per refinement depth, reused: a Shaft is a few KiB, not worth rebuilding.
    std::vector<std::unique_ptr<Shaft>> shafts;
    Shaft& shaft(int depth) {
        while (shafts.size() <= std::size_t(depth))
            shafts.push_back(std::make_unique<Shaft>());
        return *shafts[depth];
    }
    std::vector<uint32_t> blockers;  // a stack of blocker lists, one per refinement level
    std::vector<Visibility> visibility;  // per pair of the current cluster pair
    std::vector<uint64_t> cursor;  // per row of the block: next upper slot
    std::vector<uint32_t> columnCursor;  // per column: mirrored entries written by the block
    uint32_t firstRow = 0;  // of the block
};

// Bounds of two point sets.
Bounds3d boundsOf(std::span<const Vec3d> a, std::span<const Vec3d> b) {
    Bounds3d bounds;
    for (const Vec3d& v : a)
        bounds.extend(v);
    for (const Vec3d& v : b)
        bounds.extend(v);
    return bounds;
}

// The plane tolerance of geometry within `bounds` (scene units).
double toleranceOf(const Bounds3d& bounds) {
    double magnitude = 0;
    for (int axis = 0; axis < 3; ++axis)
        magnitude = std::max({magnitude, std::fabs(bounds.lo[axis]), std::fabs(bounds.hi[axis])});
    return kShaftToleranceRelative * bounds.diagonal() + kRoundingRelative * magnitude;
}

class PairLoop {
public:
    PairLoop(const PatchMesh& mesh, const FormFactorSettings& settings, PairEvaluator& evaluator)
        : mesh_(mesh),
          settings_(settings),
          evaluator_(evaluator),
          n_(static_cast<uint32_t>(mesh.patchCount())),
          geometry_(kernelGeometry(mesh)),
          clusters_(buildPatchClusters(mesh, kShaftToleranceRelative)),
          bvh_(clusters_.blockers),
          candidates_(n_),
          batchPairs_(std::max<std::size_t>(
              1, std::min<std::size_t>(evaluator.batchPairs(), kWavePairs))) {}

    Expected<FormFactorResult> run();

private:
    bool culling() const { return settings_.raysPerPair > 0 && settings_.shaftCulling; }
    std::pair<double, double> heightsAbove(const ClusterNode& a, const ClusterNode& b) const;
    double clusterPairScale(const ClusterNode& a, const ClusterNode& b) const;
    bool clusterFacesAway(const ClusterNode& a, const ClusterNode& b) const;
    bool clusterFacesToward(const ClusterNode& a, const ClusterNode& b) const;
    SkipPlane clusterPlane(const ClusterNode& cluster) const {
        const Vec3d& normal = mesh_.normals[cluster.begin];
        return {normal, dot(normal, mesh_.positions[mesh_.patches[cluster.begin][0]])};
    }
    void countCandidates();
    void calibrate();
    void computeBlock(std::size_t block, ThreadScratch& scratch, BlockOutput& out);
    void computeCluster(std::size_t block, std::size_t a, ThreadScratch& scratch, BlockOutput& out);
    void refine(uint32_t nodeA, uint32_t nodeB, std::size_t lo, std::size_t hi, int depth,
                const ClusterNode& rowCluster, const ClusterNode& columnCluster,
                ThreadScratch& scratch, BlockOutput& out) const;
    bool covered(const ClusterNode& a, const ClusterNode& b, const uint32_t* blockers,
                 std::size_t count) const;
    Expected<void> evaluate(const std::vector<BlockOutput>& outputs, bool traced);
    void buildRowBlocks();
    // Stores F_ij and, by reciprocity, F_ji = F_ij A_i / A_j (rounded once, from the float).
    void setPair(uint64_t slot, uint64_t mirrorSlot, uint32_t i, uint32_t j, float fij) {
        matrix_.values[slot] = fij;
        matrix_.values[mirrorSlot] =
            static_cast<float>(double(fij) * (mesh_.areas[i] / mesh_.areas[j]));
    }
    // Estimated seconds (one thread) of tracing `pairs` pairs.
    double traceCost(uint64_t pairs) const {
        return double(pairs) * settings_.raysPerPair * stats_.costRaySeconds * rayScale_;
    }
    // Calibrated seconds (one thread) of `children` sub-shafts filtering `blockers` blockers,
    // each also scanned by the cover test, before the online correction.
    double splitBase(int children, std::size_t blockers) const {
        return double(children) *
            (stats_.costShaftSeconds + 2.0 * double(blockers) * stats_.costTestSeconds);
    }
    // After each wave, the model corrects its own bias: the measured time of culling against
    // what the calibrated model predicted for it (cumulative, clamped to [1/4, 16]); the rays'
    // cost from the wave's batches (rayScale_); and the gate: culling stays on only while it
    // has saved more ray time than it took.
    void correctCosts(const std::vector<BlockOutput>& outputs, const WaveEvaluation& wave);

    const PatchMesh& mesh_;
    const FormFactorSettings& settings_;
    PairEvaluator& evaluator_;
    uint32_t n_;
    std::vector<PatchGeometry> geometry_;
    PatchClusters clusters_;
    BlockerBvh bvh_;
    CandidateBitmap candidates_;
    std::size_t batchPairs_;
    bool costModel_ = false;  // on once calibrated
    double cullScale_ = 1;  // measured / predicted culling time so far
    double cullSeconds_ = 0, cullPredicted_ = 0;
    // The rays' correction, from the waves' own evaluation: thread seconds of the clear pairs'
    // batches (kernel only) per pair, and of the traced batches less the kernel of their open
    // pairs per ray; measured / calibrated ray cost, clamped to [1/4, 4].
    double rayScale_ = 1;
    double kernelSeconds_ = 0, raySeconds_ = 0;
    uint64_t kernelPairs_ = 0, raysMeasured_ = 0;
    // Open while culling has so far saved more ray time than it took; closed, only one cluster
    // pair in kGateSample is culled (to keep measuring), the rest traced.
    bool gateOpen_ = true;
    std::vector<uint32_t> lowerCount_;  // per row: candidates j < i
    std::vector<uint32_t> upperCount_;  // per row: candidates j > i
    // Row blocks: clusters [blockCluster_[r], blockCluster_[r + 1]). columnBase_[r * n + j]: the
    // candidates (k, j) with k in an earlier block, i.e. where block r's entries start in the
    // lower part of row j.
    std::vector<uint32_t> blockCluster_;
    std::vector<uint32_t> columnBase_;
    SparseMatrix matrix_;
    FormFactorStats stats_;
    // Evaluation scratch, reused across batches.
    std::vector<PairIndex> batch_;
    std::vector<float> results_;
    std::vector<const PendingPair*> owners_;  // the PendingPair of each batch_ entry
};

// The lowest and highest signed heights of b's outline (which holds every corner of b's
// patches) above a's plane.
std::pair<double, double> PairLoop::heightsAbove(const ClusterNode& a, const ClusterNode& b) const {
    const SkipPlane plane = clusterPlane(a);
    double lowest = std::numeric_limits<double>::infinity();
    double highest = -lowest;
    for (const Vec3d& v : clusters_.outline(b)) {
        const double height = dot(plane.normal, v) - plane.offset;
        lowest = std::min(lowest, height);
        highest = std::max(highest, height);
    }
    return {lowest, highest};
}

// The scale of two clusters' coordinates: their bounds' diagonal plus its farthest corner's
// distance from the origin.
double PairLoop::clusterPairScale(const ClusterNode& a, const ClusterNode& b) const {
    const Bounds3d bounds = boundsOf(clusters_.outline(a), clusters_.outline(b));
    return bounds.diagonal() + std::max(length(bounds.lo), length(bounds.hi));
}

// True when no patch of b is in front of a's plane or none of a in front of b's, so every pair
// between them faces away and the per-pair test can be skipped. "In front" allows 1e-9 of the
// two clusters' coordinates, far below facingAway's own margins, so this never drops a pair the
// kernel would keep.
bool PairLoop::clusterFacesAway(const ClusterNode& a, const ClusterNode& b) const {
    const double margin = 1e-9 * clusterPairScale(a, b);
    return heightsAbove(a, b).second <= margin || heightsAbove(b, a).second <= margin;
}

// True when every patch of b lies in front of every patch of a and the other way round by a wide
// margin, so facingAway holds for none of their pairs and they are all candidates without the
// per-pair test. The margin, 1e-3 of the clusters' coordinates, is far above anything the
// per-pair test can see differently: a cluster's normals agree to 1e-9 in cosine (5e-5 rad),
// its corners lie on its plane to rounding, and facingAway's tolerances are 1e-5 of the
// distance plus 2.4e-7 of the coordinates.
bool PairLoop::clusterFacesToward(const ClusterNode& a, const ClusterNode& b) const {
    const double margin = 1e-3 * clusterPairScale(a, b);
    return heightsAbove(a, b).first > margin && heightsAbove(b, a).first > margin;
}

void PairLoop::buildRowBlocks() {
    blockCluster_.assign(1, 0);
    uint32_t rows = 0;
    for (std::size_t c = 0; c < clusters_.clusterCount(); ++c) {
        rows += clusters_.cluster(c).end - clusters_.cluster(c).begin;
        if (rows >= kMinRowBlockRows || c + 1 == clusters_.clusterCount()) {
            blockCluster_.push_back(static_cast<uint32_t>(c + 1));
            rows = 0;
        }
    }
}

// Marks the candidate pairs and counts them per row (upper part) and per row block and column
// (lower part), then turns the column counts into each block's starting offsets.
void PairLoop::countCandidates() {
    candidates_.allocate();
    upperCount_.assign(n_, 0);
    const std::size_t blockCount = blockCluster_.size() - 1;
    columnBase_.assign(blockCount * n_, 0);
    const std::size_t clusterCount = clusters_.clusterCount();
    tbb::parallel_for(std::size_t(0), blockCount, [&](std::size_t r) {
        uint32_t* columns = columnBase_.data() + r * n_;
        for (std::size_t a = blockCluster_[r]; a < blockCluster_[r + 1]; ++a) {
            const ClusterNode& rows = clusters_.cluster(a);
            for (std::size_t b = a; b < clusterCount; ++b) {
                const ClusterNode& cols = clusters_.cluster(b);
                if (b != a && clusterFacesAway(rows, cols)) continue;
                if (b != a && clusterFacesToward(rows, cols)) {
                    for (uint32_t i = rows.begin; i < rows.end; ++i) {
                        candidates_.setRange(i, cols.begin, cols.end);
                        upperCount_[i] += cols.end - cols.begin;
                    }
                    for (uint32_t j = cols.begin; j < cols.end; ++j)
                        columns[j] += rows.end - rows.begin;
                    continue;
                }
                for (uint32_t i = rows.begin; i < rows.end; ++i) {
                    uint32_t count = 0;
                    for (uint32_t j = std::max(cols.begin, i + 1); j < cols.end; ++j) {
                        if (shared::facingAway(geometry_[i], geometry_[j])) continue;
                        candidates_.set(i, j);
                        ++columns[j];
                        ++count;
                    }
                    upperCount_[i] += count;
                }
            }
        }
    });
    lowerCount_.assign(n_, 0);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n_), [&](const auto& range) {
        for (uint32_t j = range.begin(); j != range.end(); ++j) {
            uint32_t total = 0;
            for (std::size_t r = 0; r < blockCount; ++r) {
                const uint32_t count = columnBase_[r * n_ + j];
                columnBase_[r * n_ + j] = total;
                total += count;
            }
            lowerCount_[j] = total;
        }
    });
}

// The cost model's constants, measured on this scene and backend (issue 18): the seconds of
// one ray (the backend's wall time per segment of a batch times the worker count, i.e. per
// thread, as culling runs on every worker), of one shaft with its blocker query, of one shaft
// build and of one shaft-polygon test. Samples: up to 64 distinct cluster pairs spread over the
// matrix that face each other, and up to 256 of their candidate pairs for the rays, evaluated
// with 17K and with K rays (best of 3): the difference is 16K rays a pair, the kernel cancels.
// When the rays cannot be told from noise (0), the model stays off: every cluster pair is culled.
void PairLoop::calibrate() {
    const std::size_t clusterCount = clusters_.clusterCount();
    if (!culling() || !settings_.costModel || clusterCount < 2) return;
    struct Sample {
        std::size_t a, b;
    };
    constexpr std::size_t kPairs = 256;
    std::vector<Sample> samples;
    std::vector<PairIndex> pairs;
    for (uint32_t s = 0; s < 4096 && samples.size() < 64; ++s) {
        const std::size_t a = shared::pcgHash(2 * s + 1) % clusterCount;
        const std::size_t b = shared::pcgHash(2 * s + 2) % clusterCount;
        if (a == b) continue;
        const std::size_t lo = std::min(a, b), hi = std::max(a, b);
        if (std::any_of(samples.begin(), samples.end(),
                        [&](const Sample& x) { return x.a == lo && x.b == hi; }) ||
            clusterFacesAway(clusters_.cluster(lo), clusters_.cluster(hi))) {
            continue;
        }
        samples.push_back({lo, hi});
        const ClusterNode& rows = clusters_.cluster(lo);
        const ClusterNode& cols = clusters_.cluster(hi);
        // A few pairs of each sample, so that the rays see the whole scene.
        std::size_t taken = 0;
        for (uint32_t i = rows.begin; i < rows.end && taken < kPairs / 32; ++i) {
            for (uint32_t j = cols.begin; j < cols.end && taken < kPairs / 32; j += 3) {
                if (candidates_.test(i, j) && pairs.size() < kPairs) {
                    pairs.push_back({i, j});
                    ++taken;
                }
            }
        }
    }
    if (samples.empty() || pairs.empty()) return;
    const double threads = std::max(1, tbb::this_task_arena::max_concurrency());
    std::vector<float> out(pairs.size());
    const auto timed = [&](int rays) {
        const auto t0 = Clock::now();
        for (std::size_t first = 0; first < pairs.size(); first += batchPairs_) {
            const std::size_t count = std::min(batchPairs_, pairs.size() - first);
            if (!evaluator_.evaluate(std::span(pairs).subspan(first, count), rays,
                                     std::span(out).subspan(first, count))) {
                return -1.0;
            }
        }
        return secondsSince(t0);
    };
    // A traced pair costs its K rays (the slope from K to 17 K rays) and the work of tracing it
    // at all (its sample streams, batching, the kernel only where a ray got through): what the
    // K-ray pass takes beyond the kernel of its open pairs (the 0-ray pass is the kernel of
    // every pair). The price of a ray is the larger of the slope and that whole cost over K:
    // where rays are cheap (an open scene) the per-pair work is most of what culling saves.
    const int perPair = settings_.raysPerPair;
    double few = 1e300, many = 1e300, kernel = 1e300;
    double openShare = 1.0;
    for (int repeat = 0; repeat < 3; ++repeat) {
        const double a = timed(perPair);
        if (a >= 0 && repeat == 0) {
            const auto open = std::count_if(out.begin(), out.end(), [](float f) { return f > 0; });
            openShare = double(open) / double(out.size());
        }
        const double b = timed(17 * perPair);
        const double c = timed(0);
        if (a < 0 || b < 0 || c < 0) return;  // the build reports the error itself
        few = std::min(few, a);
        many = std::min(many, b);
        kernel = std::min(kernel, c);
    }
    const double slope = std::max(0.0, many - few) / (16.0 * perPair);
    const double whole = std::max(0.0, few - kernel * openShare) / perPair;
    stats_.costRaySeconds = std::max(slope, whole) * threads / double(pairs.size());
    // Culling, each best of two passes (the first warms the caches): shafts with their
    // queries, shaft builds alone, and each sample shaft tested against the blockers its query
    // kept (what refinement filters).
    Shaft shaft;
    std::vector<std::vector<uint32_t>> found(samples.size());
    const auto outlines = [&](const Sample& x, const auto& use) {
        const ClusterNode& p = clusters_.cluster(x.a);
        const ClusterNode& q = clusters_.cluster(x.b);
        use(p, q, toleranceOf(boundsOf(clusters_.outline(p), clusters_.outline(q))));
    };
    double query = 1e300, build = 1e300, test = 1e300;
    uint64_t tests = 0, excluded = 0;
    for (int pass = 0; pass < 2; ++pass) {
        auto t0 = Clock::now();
        for (std::size_t k = 0; k < samples.size(); ++k) {
            outlines(samples[k], [&](const ClusterNode& p, const ClusterNode& q, double tol) {
                found[k].clear();
                if (shaft.build(clusters_.outline(p), clusters_.outline(q), tol))
                    bvh_.query(shaft, clusterPlane(p), clusterPlane(q), tol, found[k]);
            });
        }
        query = std::min(query, secondsSince(t0) / double(samples.size()));
        t0 = Clock::now();
        for (const Sample& x : samples) {
            outlines(x, [&](const ClusterNode& p, const ClusterNode& q, double tol) {
                shaft.build(clusters_.outline(p), clusters_.outline(q), tol);
            });
        }
        build = std::min(build, secondsSince(t0) / double(samples.size()));
        double seconds = 0;
        tests = 0;
        for (std::size_t k = 0; k < samples.size(); ++k) {
            outlines(samples[k], [&](const ClusterNode& p, const ClusterNode& q, double tol) {
                if (found[k].empty() ||
                    !shaft.build(clusters_.outline(p), clusters_.outline(q), tol)) {
                    return;
                }
                const auto t1 = Clock::now();
                for (uint32_t blocker : found[k])
                    excluded += shaft.excludesPolygon(clusters_.blockers[blocker]) ? 1 : 0;
                seconds += secondsSince(t1);
                tests += found[k].size();
            });
        }
        if (tests > 0) test = std::min(test, seconds / double(tests));
    }
    stats_.costQuerySeconds = query;
    stats_.costShaftSeconds = build;
    // No sample shaft kept a blocker: refinement never runs, so its price does not matter.
    stats_.costTestSeconds = tests > 0 ? test : 0;
    [[maybe_unused]] volatile uint64_t keep = excluded;  // the timed tests are not dead code
    costModel_ = stats_.costRaySeconds > 0;
}

bool PairLoop::covered(const ClusterNode& a, const ClusterNode& b, const uint32_t* blockers,
                       std::size_t count) const {
    const Bounds3d bounds = boundsOf(clusters_.outline(a), clusters_.outline(b));
    // Segments stop kSegmentMargin of their length short of each end: a covering face must
    // clear that much of the shaft's size too.
    const double margin =
        std::max(toleranceOf(bounds), 4.0 * RayCaster::kSegmentMargin * bounds.diagonal());
    for (std::size_t k = 0; k < count; ++k) {
        const uint32_t face = clusters_.blockerFace[blockers[k]];
        if (face != kNoFace &&
            faceCoversShaft(clusters_.faces[face], clusters_.outline(a), clusters_.outline(b),
                            margin)) {
            return true;
        }
    }
    return false;
}

// Shaft refinement of the node pair (nodeA, nodeB) whose blockers are scratch.blockers[lo, hi):
// an empty list makes every pair clear, a covering solid face makes every pair hidden, a small
// node pair, or one whose smaller shafts the cost model prices above its rays, is traced;
// otherwise both nodes are halved and each of the four sub-shafts filters the list (a sub-shaft
// lies inside its parent, so no blocker is missed).
void PairLoop::refine(uint32_t nodeA, uint32_t nodeB, std::size_t lo, std::size_t hi, int depth,
                      const ClusterNode& rowCluster, const ClusterNode& columnCluster,
                      ThreadScratch& scratch, BlockOutput& out) const {
    FormFactorStats& stats = out.stats;
    const ClusterNode& a = clusters_.nodes[nodeA];
    const ClusterNode& b = clusters_.nodes[nodeB];
    const auto mark = [&](Visibility v) {
        const uint32_t width = columnCluster.end - columnCluster.begin;
        const uint32_t* order = clusters_.order.data();
        for (uint32_t p = a.begin; p < a.end; ++p) {
            Visibility* row =
                scratch.visibility.data() + std::size_t(order[p] - rowCluster.begin) * width;
            for (uint32_t q = b.begin; q < b.end; ++q)
                row[order[q] - columnCluster.begin] = v;
        }
    };
    if (lo == hi) {
        mark(depth == 0 ? Visibility::ClearCluster : Visibility::ClearRefined);
        return;
    }
    if (covered(a, b, scratch.blockers.data() + lo, hi - lo)) {
        mark(Visibility::Covered);
        return;
    }
    const uint64_t pairs = uint64_t(a.end - a.begin) * (b.end - b.begin);
    if (pairs <= kMinRefinePairs) {
        mark(Visibility::Trace);
        return;
    }
    const int countA = a.firstChild != 0 ? 2 : 1;
    const int countB = b.firstChild != 0 ? 2 : 1;
    const double split = splitBase(countA * countB, hi - lo);
    const double benefit = pairs <= kSmallNodePairs ? kSmallRefineBenefit : kRefineBenefit;
    if (costModel_ && cullScale_ * split > benefit * traceCost(pairs)) {
        ++stats.costStoppedRefinements;
        mark(Visibility::Trace);
        return;
    }
    out.cullPredicted += split;
    // Halve both nodes (or the one that still can be): four (or two) smaller shafts.
    const uint32_t childrenA[2] = {a.firstChild != 0 ? a.firstChild : nodeA, a.firstChild + 1};
    const uint32_t childrenB[2] = {b.firstChild != 0 ? b.firstChild : nodeB, b.firstChild + 1};
    for (int x = 0; x < countA; ++x) {
        for (int y = 0; y < countB; ++y) {
            const ClusterNode& ca = clusters_.nodes[childrenA[x]];
            const ClusterNode& cb = clusters_.nodes[childrenB[y]];
            const std::size_t childLo = scratch.blockers.size();
            Shaft& shaft = scratch.shaft(depth + 1);
            ++stats.shaftsBuilt;
            const bool valid =
                shaft.build(clusters_.outline(ca), clusters_.outline(cb),
                            toleranceOf(boundsOf(clusters_.outline(ca), clusters_.outline(cb))));
            for (std::size_t k = lo; k < hi; ++k) {
                const uint32_t blocker = scratch.blockers[k];
                if (!valid || !shaft.excludesPolygon(clusters_.blockers[blocker])) {
                    scratch.blockers.push_back(blocker);
                }
            }
            refine(childrenA[x], childrenB[y], childLo, scratch.blockers.size(), depth + 1,
                   rowCluster, columnCluster, scratch, out);
            scratch.blockers.resize(childLo);
        }
    }
}

// One row block: its clusters in order, each against every cluster from itself on. Upper entries
// go to each row's running cursor; mirrored entries F_ji = F_ij A_i / A_j go to row j at the
// block's column base plus a per-column cursor, so every row ends up in ascending column order
// with no pass over the matrix afterwards.
void PairLoop::computeBlock(std::size_t block, ThreadScratch& scratch, BlockOutput& out) {
    const uint32_t firstRow = clusters_.cluster(blockCluster_[block]).begin;
    const uint32_t endRow = clusters_.cluster(blockCluster_[block + 1] - 1).end;
    scratch.cursor.resize(endRow - firstRow);
    for (uint32_t i = firstRow; i < endRow; ++i)
        scratch.cursor[i - firstRow] = matrix_.rowOffsets[i] + lowerCount_[i];
    scratch.columnCursor.assign(n_, 0);
    scratch.firstRow = firstRow;
    for (std::size_t a = blockCluster_[block]; a < blockCluster_[block + 1]; ++a)
        computeCluster(block, a, scratch, out);
}

void PairLoop::computeCluster(std::size_t block, std::size_t a, ThreadScratch& scratch,
                              BlockOutput& out) {
    const ClusterNode& rowCluster = clusters_.cluster(a);
    const uint32_t* columnBase = columnBase_.data() + block * n_;
    const bool visibility = settings_.raysPerPair > 0;
    FormFactorStats& stats = out.stats;
    for (std::size_t b = a; b < clusters_.clusterCount(); ++b) {
        const ClusterNode& columnCluster = clusters_.cluster(b);
        const uint32_t width = columnCluster.end - columnCluster.begin;
        const uint64_t blockPairs = a == b ? uint64_t(width) * (width - 1) / 2
                                           : uint64_t(rowCluster.end - rowCluster.begin) * width;
        out.pairs += blockPairs;
        uint64_t blockCandidates = 0;
        for (uint32_t i = rowCluster.begin; i < rowCluster.end; ++i) {
            for (uint32_t j = std::max(columnCluster.begin, i + 1); j < columnCluster.end; ++j)
                blockCandidates += candidates_.test(i, j) ? 1 : 0;
        }
        stats.facingAway += blockPairs - blockCandidates;
        if (blockCandidates == 0) continue;
        // Classify the block's pairs: shaft of the cluster pair, then refinement. Pairs inside
        // one cluster (nearly coplanar) are simply traced, and so are cluster pairs whose
        // rays the cost model prices below one shaft query.
        scratch.visibility.assign(std::size_t(rowCluster.end - rowCluster.begin) * width,
                                  visibility ? Visibility::Trace : Visibility::ClearCluster);
        if (culling() && a != b) {
            if (costModel_ &&
                ((!gateOpen_ && (a + b) % kGateSample != 0) ||
                 traceCost(blockCandidates) < cullScale_ * stats_.costQuerySeconds)) {
                ++stats.costTracedClusterPairs;
            } else {
                ++stats.culledClusterPairs;
                const auto cullStart = Clock::now();
                out.cullPredicted += stats_.costQuerySeconds;
                Shaft& shaft = scratch.shaft(0);
                ++stats.shaftsBuilt;
                const double tolerance = toleranceOf(
                    boundsOf(clusters_.outline(rowCluster), clusters_.outline(columnCluster)));
                if (shaft.build(clusters_.outline(rowCluster), clusters_.outline(columnCluster),
                                tolerance)) {
                    scratch.blockers.clear();
                    bvh_.query(shaft, clusterPlane(rowCluster), clusterPlane(columnCluster),
                               tolerance, scratch.blockers);
                    refine(clusters_.clusterRoot[a], clusters_.clusterRoot[b], 0,
                           scratch.blockers.size(), 0, rowCluster, columnCluster, scratch, out);
                }
                out.cullSeconds += secondsSince(cullStart);
            }
        }
        for (uint32_t i = rowCluster.begin; i < rowCluster.end; ++i) {
            uint64_t& cursor = scratch.cursor[i - scratch.firstRow];
            const Visibility* rowVisibility =
                scratch.visibility.data() + std::size_t(i - rowCluster.begin) * width;
            for (uint32_t j = std::max(columnCluster.begin, i + 1); j < columnCluster.end; ++j) {
                if (!candidates_.test(i, j)) continue;
                const uint64_t slot = cursor++;
                const uint64_t mirrorSlot =
                    matrix_.rowOffsets[j] + columnBase[j] + scratch.columnCursor[j]++;
                matrix_.columns[slot] = j;
                matrix_.columns[mirrorSlot] = i;
                const Visibility v = rowVisibility[j - columnCluster.begin];
                if (v == Visibility::Covered) {
                    matrix_.values[slot] = 0.0f;
                    matrix_.values[mirrorSlot] = 0.0f;
                    ++stats.coveredPairs;
                } else if (v == Visibility::Trace) {
                    out.trace.push_back({slot, mirrorSlot, i, j});
                } else {
                    out.clear.push_back({slot, mirrorSlot, i, j});
                    if (!visibility) continue;
                    (v == Visibility::ClearCluster ? stats.clearClusterShafts
                                                   : stats.clearPairShafts) += 1;
                }
            }
        }
    }
}

// Evaluates the wave's clear (traced = false: no rays) or traced pairs in the backend's batches,
// in block order, and stores both entries of each.
Expected<void> PairLoop::evaluate(const std::vector<BlockOutput>& outputs, bool traced) {
    const int rays = traced ? settings_.raysPerPair : 0;
    std::vector<const PendingPair*>& owners = owners_;
    owners.clear();
    const auto flush = [&]() -> Expected<void> {
        if (batch_.empty()) return {};
        if (isCancelled(settings_.cancel)) return Error{kInterruptedMessage};
        results_.assign(batch_.size(), 0.0f);
        Expected<void> done = evaluator_.evaluate(batch_, rays, results_);
        if (!done) return withContext(done.error(), concat("backend '", evaluator_.name(), "'"));
        for (std::size_t k = 0; k < batch_.size(); ++k) {
            const PendingPair& pair = *owners[k];
            const float fij = results_[k];
            if (!(std::isfinite(fij) && fij >= 0.0f)) {
                return Error{concat("backend '", evaluator_.name(), "' returned F_", pair.i, ",",
                                    pair.j, " = ", fij, " (not a finite factor >= 0)")};
            }
            setPair(pair.slot, pair.mirrorSlot, pair.i, pair.j, fij);
            if (fij == 0.0f) (traced ? stats_.hiddenPairs : stats_.zeroFactor) += 1;
        }
        if (traced) {
            stats_.tracedPairs += batch_.size();
            stats_.raysCast += batch_.size() * uint64_t(rays);
        }
        batch_.clear();
        owners.clear();
        return {};
    };
    for (const BlockOutput& out : outputs) {
        for (const PendingPair& pair : traced ? out.trace : out.clear) {
            batch_.push_back({pair.i, pair.j});
            owners.push_back(&pair);
            if (batch_.size() == batchPairs_) {
                Expected<void> done = flush();
                if (!done) return done;
            }
        }
    }
    return flush();
}

void PairLoop::correctCosts(const std::vector<BlockOutput>& outputs, const WaveEvaluation& wave) {
    for (const BlockOutput& out : outputs) {
        cullSeconds_ += out.cullSeconds;
        cullPredicted_ += out.cullPredicted;
    }
    if (cullPredicted_ > 0) cullScale_ = std::clamp(cullSeconds_ / cullPredicted_, 0.25, 16.0);
    stats_.costCullScale = cullScale_;
    kernelSeconds_ += wave.clearSeconds;
    kernelPairs_ += wave.clearPairs;
    if (kernelPairs_ > 0 && wave.rays > 0) {
        const double kernel = kernelSeconds_ / double(kernelPairs_);
        raySeconds_ += std::max(0.0, wave.tracedSeconds - double(wave.openTraced) * kernel);
        raysMeasured_ += wave.rays;
        rayScale_ =
            std::clamp(raySeconds_ / double(raysMeasured_) / stats_.costRaySeconds, 0.25, 4.0);
        stats_.costRayScale = rayScale_;
    }
    // What culling saved: the rays of every pair it decided (clear or covered; the stats are
    // cumulative, this wave's already added).
    const uint64_t resolved =
        stats_.clearClusterShafts + stats_.clearPairShafts + stats_.coveredPairs;
    gateOpen_ = cullSeconds_ <= traceCost(resolved);
    stats_.costGateClosedWaves += gateOpen_ ? 0 : 1;
}

Expected<FormFactorResult> PairLoop::run() {
    const auto start = Clock::now();
    stats_.patches = n_;
    stats_.pairs = n_ < 2 ? 0 : uint64_t(n_) * (n_ - 1) / 2;
    stats_.clusters = clusters_.clusterCount();

    buildRowBlocks();
    countCandidates();
    uint64_t candidatePairs = 0;
    for (uint32_t i = 0; i < n_; ++i)
        candidatePairs += upperCount_[i];
    stats_.countSeconds = secondsSince(start);
    stats_.slots = 2 * candidatePairs;
    uint64_t blockRows = 2 * kMaxClusterSize;
    for (std::size_t b = 0; b + 1 < blockCluster_.size(); ++b) {
        blockRows = std::max<uint64_t>(blockRows,
                                       clusters_.cluster(blockCluster_[b + 1] - 1).end -
                                           clusters_.cluster(blockCluster_[b]).begin);
    }
    stats_.workBytes = formFactorWorkBytes(n_, candidatePairs, blockRows);
    if (settings_.maxMemoryBytes > 0 && stats_.workBytes > settings_.maxMemoryBytes) {
        return Error{concat("the view-factor matrix needs ",
                            formatBytes(static_cast<double>(stats_.workBytes)), " for ",
                            formatCount(candidatePairs), " facing pairs of ", formatCount(n_),
                            " patches, more than --max-memory ",
                            formatBytes(static_cast<double>(settings_.maxMemoryBytes)),
                            "; use fewer patches (a larger --subdivide) or raise --max-memory")};
    }

    matrix_.size = n_;
    matrix_.rowOffsets.assign(std::size_t(n_) + 1, 0);
    for (uint32_t i = 0; i < n_; ++i)
        matrix_.rowOffsets[i + 1] = matrix_.rowOffsets[i] + lowerCount_[i] + upperCount_[i];
    resizeOnHugePages(matrix_.columns, stats_.slots);
    resizeOnHugePages(matrix_.values, stats_.slots);

    const auto pairStart = Clock::now();
    const auto calibrateStart = Clock::now();
    calibrate();
    stats_.costCalibrationSeconds = stats_.costRaySeconds > 0 ? secondsSince(calibrateStart) : 0;
    {
        Progress progress("view factors", stats_.pairs, "pairs",
                          settings_.progress && progressEnabledByDefault(), settings_.onProgress);
        tbb::enumerable_thread_specific<ThreadScratch> scratch;
        std::vector<BlockOutput> outputs;
        const std::size_t threads = std::max(1, tbb::this_task_arena::max_concurrency());
        const std::size_t blockCount = blockCluster_.size() - 1;
        for (std::size_t first = 0; first < blockCount;) {
            if (isCancelled(settings_.cancel)) return Error{kInterruptedMessage};
            // A wave: blocks until about kWavePairs candidates, and at least one block a thread
            // (a block is classified by one thread: the large clusters of scattered runs would
            // otherwise leave the other threads idle).
            std::size_t last = first;
            uint64_t wave = 0;
            while (last < blockCount && (last - first < threads || wave < kWavePairs)) {
                const uint32_t begin = clusters_.cluster(blockCluster_[last]).begin;
                const uint32_t end = clusters_.cluster(blockCluster_[last + 1] - 1).end;
                for (uint32_t i = begin; i < end; ++i)
                    wave += upperCount_[i];
                ++last;
            }
            outputs.resize(last - first);
            for (BlockOutput& out : outputs)
                out.reset();
            tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last, 1),
                              [&](const tbb::blocked_range<std::size_t>& range) {
                                  for (std::size_t block = range.begin(); block != range.end();
                                       ++block) {
                                      if (isCancelled(settings_.cancel)) break;
                                      computeBlock(block, scratch.local(), outputs[block - first]);
                                  }
                              });
            if (isCancelled(settings_.cancel)) return Error{kInterruptedMessage};
            WaveEvaluation evaluated;
            const uint64_t raysBefore = stats_.raysCast;
            const uint64_t hiddenBefore = stats_.hiddenPairs;
            const uint64_t tracedBefore = stats_.tracedPairs;
            for (bool traced : {false, true}) {
                const auto evaluateStart = Clock::now();
                Expected<void> done = evaluate(outputs, traced);
                if (!done) return done.error();
                (traced ? evaluated.tracedSeconds : evaluated.clearSeconds) =
                    secondsSince(evaluateStart) * double(threads);
            }
            evaluated.rays = stats_.raysCast - raysBefore;
            evaluated.openTraced =
                (stats_.tracedPairs - tracedBefore) - (stats_.hiddenPairs - hiddenBefore);
            uint64_t pairs = 0;
            for (const BlockOutput& out : outputs) {
                addStats(stats_, out.stats);
                pairs += out.pairs;
                evaluated.clearPairs += out.clear.size();
            }
            if (costModel_) correctCosts(outputs, evaluated);
            progress.advance(pairs);
            first = last;
        }
    }
    stats_.pairSeconds = secondsSince(pairStart);
    if (isCancelled(settings_.cancel)) return Error{kInterruptedMessage};

    const auto compactStart = Clock::now();
    candidates_.words = {};
    columnBase_ = {};
    dropZeros(matrix_);
    if (settings_.raysPerPair > 0) {
        const RowSumCap cap = capRowSums(matrix_);
        stats_.rowsCapped = cap.rowsCapped;
        stats_.largestRowSum = cap.largestRowSum;
    }
    stats_.compactSeconds = secondsSince(compactStart);
    stats_.nonzeros = matrix_.nonzeroCount();
    stats_.totalSeconds = secondsSince(start);
    return FormFactorResult{std::move(matrix_), stats_};
}

}  // namespace

namespace {

constexpr FormFactorMethod kMethods[] = {FormFactorMethod::Hybrid, FormFactorMethod::Riemann,
                                         FormFactorMethod::Nusselt, FormFactorMethod::Stochastic};

}  // namespace

bool parseFormFactorMethod(const std::string& name, FormFactorMethod& method) {
    for (FormFactorMethod m : kMethods) {
        if (name == formFactorMethodName(m)) {
            method = m;
            return true;
        }
    }
    return false;
}

std::vector<std::string> formFactorMethodNames() {
    std::vector<std::string> names;
    for (FormFactorMethod m : kMethods)
        names.push_back(formFactorMethodName(m));
    return names;
}

const char* formFactorMethodName(FormFactorMethod method) {
    switch (method) {
        case FormFactorMethod::Riemann:
            return "riemann";
        case FormFactorMethod::Nusselt:
            return "nusselt";
        case FormFactorMethod::Stochastic:
            return "stochastic";
        case FormFactorMethod::Hybrid:
            return "hybrid";
    }
    return "?";
}

uint64_t formFactorWorkBytes(uint64_t patchCount, uint64_t candidatePairs, uint64_t blockRows) {
    const uint64_t n = patchCount;
    const uint64_t rowBlocks = n / kMinRowBlockRows + 1;
    const uint64_t threads = std::max(1, tbb::this_task_arena::max_concurrency());
    // A wave's pending pairs (at most kWavePairs plus one block, or one block a thread: each of
    // at most blockRows rows) and one batch of pairs with their results.
    const uint64_t wave =
        std::min(candidatePairs, std::max(kWavePairs + blockRows * n, threads * blockRows * n));
    const uint64_t batch = std::min(candidatePairs, kWavePairs);
    return sparseMatrixBytes(n, 2 * candidatePairs) + CandidateBitmap::bytes(n) +
        4 * n * rowBlocks + 4 * n * (2 + threads) + wave * sizeof(PendingPair) +
        batch * (sizeof(PairIndex) + sizeof(float) + sizeof(void*));
}

Expected<FormFactorResult> computeFormFactors(const PatchMesh& mesh,
                                              const FormFactorSettings& settings,
                                              PairEvaluator& evaluator) {
    if (settings.method == FormFactorMethod::Stochastic) {
        return Error{concat("backend '", evaluator.name(),
                            "' has no stochastic method (its rays are per patch, not per pair); "
                            "use --method hybrid, riemann or nusselt, or --backend cpu")};
    }
    if (settings.quadratureLevel < 0 || settings.quadratureLevel > DAISY_MAX_QUADRATURE_LEVEL) {
        return Error{concat("--quadrature ", settings.quadratureLevel, " is outside 0..",
                            DAISY_MAX_QUADRATURE_LEVEL)};
    }
    if (settings.raysPerPair < 0 || settings.stochasticRays < 1) {
        return Error{"ray counts must be positive"};
    }
    if (mesh.patchCount() > UINT32_MAX - 1) return Error{"too many patches for 32-bit indices"};
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    return arena.execute([&]() -> Expected<FormFactorResult> {
        PairLoop loop(mesh, settings, evaluator);
        return loop.run();
    });
}

Expected<FormFactorResult> computeFormFactors(const PatchMesh& mesh,
                                              const FormFactorSettings& settings,
                                              const RayCaster& rays) {
    if (settings.method != FormFactorMethod::Stochastic) {
        const std::unique_ptr<PairEvaluator> evaluator = makeRayPairEvaluator(mesh, settings, rays);
        return computeFormFactors(mesh, settings, *evaluator);
    }
    if (settings.raysPerPair < 0 || settings.stochasticRays < 1) {
        return Error{"ray counts must be positive"};
    }
    if (mesh.patchCount() > UINT32_MAX - 1) return Error{"too many patches for 32-bit indices"};
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    return arena.execute([&]() { return computeStochastic(mesh, settings, rays); });
}

}  // namespace daisy
