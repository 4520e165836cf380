#pragma once
// The form-factor driver's pair loop (radiosity/form_factors.h says what it does), shared by
// its files and included by nothing else: form_factors_pair_loop.cpp (the waves, the batches
// handed to the PairEvaluator, the CSR writes and the final compaction),
// form_factors_candidates.cpp (the candidate pass and the row blocks), form_factors_culling.cpp
// (each block's shaft culling and refinement) and form_factors_cost_model.cpp (the prices that
// decide whether culling pays). One class because they share the matrix being built,
// the clusters and the cost model's state.
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "radiosity/blocker_bvh.h"
#include "radiosity/form_factors.h"
#include "radiosity/kernel_inputs.h"
#include "radiosity/pair_evaluator.h"
#include "radiosity/patch_clusters.h"
#include "radiosity/shaft.h"
#include "shared/gpu_types.h"

namespace daisy::detail {

using shared::PairFactors;
using shared::PairIndex;
using shared::PatchGeometry;

// Shafts treat points within this fraction of the size of what they are built from (the two
// outlines' bounding box) as on a plane, plus kRoundingRelative of those coordinates' magnitude
// (a few float roundings of where they are): relative to the patches involved, never to the
// scene, so one far triangle changes no nearby decision.
constexpr double kShaftToleranceRelative = 1e-6;
constexpr double kRoundingRelative = 2.5e-7;
// Consecutive clusters are grouped into row blocks of at least this many rows, one task each.
// Each block keeps a column table of n uint32 (where its rows' mirrored entries start in every
// lower row), so the tables cost n^2 / 8 bytes in all, about 1/40 of the matrix.
constexpr uint32_t kMinRowBlockRows = 32;
// Node pairs with at most this many patch pairs are traced rather than refined.
constexpr uint64_t kMinRefinePairs = 4;
// Row blocks are classified in waves of about this many candidate pairs, and at least
// kMinWaveBlocks blocks (classification work for that many threads), whose pairs are then
// evaluated in the backend's batches: the pending lists are bounded by the wave, not the scene.
// Waves depend on the geometry alone, never on the thread count: the cost model's gate, updated
// between waves, must see the same history on every machine.
constexpr uint64_t kWavePairs = uint64_t(1) << 20;
constexpr std::size_t kMinWaveBlocks = 8;
// The cost model refines a node pair only while its shafts cost less than this fraction of
// tracing its pairs: a split resolves only part of its pairs (most small shafts are truly
// partly blocked), so it must be clearly cheaper to pay.
constexpr double kRefineBenefit = 0.5;
// Node pairs of at most kSmallNodePairs patch pairs are refined only when their shafts cost under
// kSmallRefineBenefit of tracing them: the last splits mostly leave partly blocked leaves. On the
// cpu backend this stops at 16 pairs (the pair loop 10-20% faster on every scene of the family
// and the Blender Cornell box than refining down to 4, with a quarter more rays); a backend whose
// rays are dear (vulkan on lavapipe) still refines to 4 (docs/performance.md).
constexpr uint64_t kSmallNodePairs = 16;
constexpr double kSmallRefineBenefit = 0.125;
// With the gate closed (culling has cost more than its rays saved), one cluster pair in this
// many is still culled, so the gate can open again where culling starts to pay.
constexpr std::size_t kGateSample = 8;
// The cost model's prices of culling (form_factors_cost_model.cpp): nanoseconds of one thread of
// the reference machine (docs/performance.md), fixed, so that its choices are a function of the
// geometry and the backend alone. Measured there (thread CPU time, the family's scenes): a shaft
// build 520-2000 ns; a shaft-polygon test of a blocker a query kept (refinement, cover test)
// 50-190 ns; within a blocker query, a BVH node 35 ns and a blocker 45 ns.
constexpr double kShaftNs = 900;
constexpr double kTestNs = 100;
constexpr double kQueryNodeNs = 35;
constexpr double kQueryBlockerNs = 45;

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

// Adds part's per-block counters into total.
void addStats(FormFactorStats& total, const FormFactorStats& part);

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
    double cullNs = 0;  // the culling it did, priced by the cost model (counted, not timed)
    // Empties the output for another block, keeping the lists' storage: a wave's lists are
    // hundreds of MB in all, and fresh storage each wave cost its page faults again.
    void reset() {
        clear.clear();
        trace.clear();
        stats = {};
        pairs = 0;
        cullNs = 0;
    }
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
Bounds3d boundsOf(std::span<const Vec3d> a, std::span<const Vec3d> b);

// The plane tolerance of geometry within `bounds` (scene units).
double toleranceOf(const Bounds3d& bounds);

class PairLoop {
public:
    PairLoop(const PatchMesh& mesh, const FormFactorSettings& settings, PairEvaluator& evaluator)
        : mesh_(mesh),
          settings_(settings),
          evaluator_(evaluator),
          n_(static_cast<uint32_t>(mesh.patchCount())),
          geometry_(kernelPatches(mesh)),
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
    // The price of one blocker query that visited `work`'s nodes and blockers, with its shaft.
    static double queryNs(const BlockerQueryWork& work) {
        return kShaftNs + double(work.nodes) * kQueryNodeNs +
            double(work.blockers) * kQueryBlockerNs;
    }
    void computeBlock(std::size_t block, ThreadScratch& scratch, BlockOutput& out);
    void computeCluster(std::size_t block, std::size_t a, ThreadScratch& scratch, BlockOutput& out);
    void refine(uint32_t nodeA, uint32_t nodeB, std::size_t lo, std::size_t hi, int depth,
                const ClusterNode& rowCluster, const ClusterNode& columnCluster,
                ThreadScratch& scratch, BlockOutput& out) const;
    bool covered(const ClusterNode& a, const ClusterNode& b, const uint32_t* blockers,
                 std::size_t count, BlockOutput& out) const;
    Expected<void> evaluate(const std::vector<BlockOutput>& outputs, bool traced);
    void buildRowBlocks();
    // Stores F_ij and, by reciprocity, F_ji = F_ij A_i / A_j (rounded once, from the float, with
    // the mesh's double areas): the evaluator's own F_ji is not stored, so F is reciprocal in
    // the mesh's areas to one rounding on every backend.
    void setPair(uint64_t slot, uint64_t mirrorSlot, uint32_t i, uint32_t j, float fij) {
        matrix_.values[slot] = fij;
        matrix_.values[mirrorSlot] =
            static_cast<float>(double(fij) * (mesh_.areas[i] / mesh_.areas[j]));
    }
    // The model's price (ns, one thread) of tracing `pairs` pairs.
    double traceCost(uint64_t pairs) const {
        return double(pairs) * settings_.raysPerPair * stats_.costRayNs;
    }
    // The model's price of `children` sub-shafts filtering `blockers` blockers, each also
    // scanned by the cover test.
    static double splitCost(int children, std::size_t blockers) {
        return double(children) * (kShaftNs + 2.0 * double(blockers) * kTestNs);
    }
    // After each wave, the gate: culling stays on only while it has saved more (the rays of the
    // pairs it decided) than it cost, both priced by the model from what was counted.
    void updateGate(const std::vector<BlockOutput>& outputs);

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
    // Open while culling has so far saved more than it cost (the model's prices of the work
    // counted); closed, only one cluster pair in kGateSample is culled (to keep counting), the
    // rest traced.
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
    std::vector<PairFactors> results_;
    std::vector<const PendingPair*> owners_;  // the PendingPair of each batch_ entry
};

}  // namespace daisy::detail
