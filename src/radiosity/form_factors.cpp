// The deterministic pair loop (DESIGN.md section 3), one class with its culling and storage;
// about 600 lines because they share its state. The stochastic method is in
// stochastic_form_factors.cpp.
#include "radiosity/form_factors.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <vector>

#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "radiosity/blocker_bvh.h"
#include "radiosity/form_factors_internal.h"
#include "radiosity/patch_clusters.h"
#include "radiosity/shaft.h"
#include "radiosity/visibility_samples.h"
#include "shared/config.h"
#include "shared/formfactor.h"
#include "shared/rng.h"
#include "shared/sampling.h"

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
using detail::methodConstant;
using detail::seed32;
using shared::PatchGeometry;
using shared::vec3;

// Shafts treat points within this fraction of the scene's diagonal as on a plane: a few float
// roundings of the coordinates, far below any modelled gap.
constexpr double kShaftToleranceRelative = 1e-6;
// Shadow segments stop this fraction of the scene's diagonal short of their patches' planes
// (shadowSegments): several float roundings of the coordinates, so the end patches never
// report themselves as blockers.
constexpr double kEndClearanceRelative = 2e-6;
// Consecutive clusters are grouped into row blocks of at least this many rows, one task each.
// Each block keeps a column table of n uint32 (where its rows' mirrored entries start in every
// lower row), so the tables cost n^2 / 8 bytes in all, about 1/40 of the matrix.
constexpr uint32_t kMinRowBlockRows = 32;

// Node pairs with at most this many patch pairs are traced rather than refined: below it, a
// further split resolves so few pairs (most such shafts are truly partly blocked) that building
// the smaller shafts costs more than the rays it saves (measured in docs/performance.md).
constexpr uint64_t kMinRefinePairs = 4;
// Pairs waiting for rays are traced once their segments reach this count (1.5 MB of scratch
// a thread), so a large --rays cannot make the scratch grow with the cluster size.
constexpr std::size_t kMaxPendingSegments = 1 << 16;

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
};

void addStats(FormFactorStats& total, const FormFactorStats& part) {
    total.facingAway += part.facingAway;
    total.zeroFactor += part.zeroFactor;
    total.clearClusterShafts += part.clearClusterShafts;
    total.clearPairShafts += part.clearPairShafts;
    total.coveredPairs += part.coveredPairs;
    total.tracedPairs += part.tracedPairs;
    total.hiddenPairs += part.hiddenPairs;
    total.openPairs += part.openPairs;
    total.raysCast += part.raysCast;
    total.shaftsBuilt += part.shaftsBuilt;
}

// What shaft culling decided for a pair of a cluster pair.
enum class Visibility : uint8_t {
    Trace,  // cast the K rays
    ClearCluster,  // V = 1: the cluster pair's shaft is empty
    ClearRefined,  // V = 1: a smaller shaft around the pair is empty
    Covered,  // V = 0: a solid face crosses the whole shaft
};

// A pair waiting for its shadow rays.
struct PendingPair {
    uint64_t slot;  // of F_ij
    uint64_t mirrorSlot;  // of F_ji
    uint32_t i, j;
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
    std::vector<PendingPair> pending;
    SegmentArrays segments;
    std::vector<uint8_t> blocked;
    std::vector<uint64_t> cursor;  // per row of the block: next upper slot
    std::vector<uint32_t> columnCursor;  // per column: mirrored entries written by the block
    uint32_t firstRow = 0;  // of the block
};

class PairLoop {
public:
    PairLoop(const PatchMesh& mesh, const FormFactorSettings& settings, const RayCaster& rays)
        : mesh_(mesh),
          settings_(settings),
          rays_(rays),
          n_(static_cast<uint32_t>(mesh.patchCount())),
          geometry_(kernelGeometry(mesh)),
          diagonal_(std::max(1e-300, meshDiagonal(mesh))),
          tolerance_(kShaftToleranceRelative * diagonal_),
          endClearance_(static_cast<float>(kEndClearanceRelative * diagonal_)),
          coverMargin_(std::max(tolerance_, 4.0 * RayCaster::kSegmentMargin * diagonal_)),
          clusters_(buildPatchClusters(mesh, tolerance_)),
          bvh_(clusters_.blockers),
          candidates_(n_),
          seed_(seed32(settings.seed)),
          method_(methodConstant(settings.method)) {}

    Expected<FormFactorResult> run();

private:
    static double meshDiagonal(const PatchMesh& mesh) {
        Bounds3d bounds;
        for (const Vec3d& p : mesh.positions)
            bounds.extend(p);
        return bounds.diagonal();
    }
    bool clusterFacesAway(const ClusterNode& a, const ClusterNode& b) const;
    SkipPlane clusterPlane(const ClusterNode& cluster) const {
        const Vec3d& normal = mesh_.normals[cluster.begin];
        return {normal, dot(normal, mesh_.positions[mesh_.patches[cluster.begin][0]])};
    }
    void countCandidates();
    void computeBlock(std::size_t block, ThreadScratch& scratch, FormFactorStats& stats,
                      Progress& progress);
    void computeCluster(std::size_t block, std::size_t a, ThreadScratch& scratch,
                        FormFactorStats& stats, Progress& progress);
    void refine(uint32_t nodeA, uint32_t nodeB, std::size_t lo, std::size_t hi, int depth,
                const ClusterNode& rowCluster, const ClusterNode& columnCluster,
                ThreadScratch& scratch, FormFactorStats& stats) const;
    bool covered(const ClusterNode& a, const ClusterNode& b, const uint32_t* blockers,
                 std::size_t count) const;
    void tracePending(ThreadScratch& scratch, FormFactorStats& stats);
    void buildRowBlocks();
    // Unoccluded F_ij of a candidate pair (>= 0), from the shared kernel in the accurate
    // direction.
    float unoccludedFactor(uint32_t i, uint32_t j) const {
        const float f =
            shared::pairFactors(method_, settings_.quadratureLevel, geometry_[i], geometry_[j]).fij;
        return f > 0.0f ? f : 0.0f;
    }
    // Stores F_ij and, by reciprocity, F_ji = F_ij A_i / A_j (rounded once, from the float).
    void setPair(uint64_t slot, uint64_t mirrorSlot, uint32_t i, uint32_t j, float fij) {
        matrix_.values[slot] = fij;
        matrix_.values[mirrorSlot] =
            static_cast<float>(double(fij) * (mesh_.areas[i] / mesh_.areas[j]));
    }

    const PatchMesh& mesh_;
    const FormFactorSettings& settings_;
    const RayCaster& rays_;
    uint32_t n_;
    std::vector<PatchGeometry> geometry_;
    double diagonal_;
    double tolerance_;
    float endClearance_;
    double coverMargin_;
    PatchClusters clusters_;
    BlockerBvh bvh_;
    CandidateBitmap candidates_;
    std::vector<uint32_t> lowerCount_;  // per row: candidates j < i
    std::vector<uint32_t> upperCount_;  // per row: candidates j > i
    // Row blocks: clusters [blockCluster_[r], blockCluster_[r + 1]). columnBase_[r * n + j]: the
    // candidates (k, j) with k in an earlier block, i.e. where block r's entries start in the
    // lower part of row j.
    std::vector<uint32_t> blockCluster_;
    std::vector<uint32_t> columnBase_;
    uint32_t seed_;
    int method_;
    SparseMatrix matrix_;
    FormFactorStats stats_;
};

// True when no patch of b is in front of a's plane or none of a in front of b's (outlines hold
// every corner), so every pair between them faces away and the per-pair test can be skipped.
// "In front" allows 1e-9 of the scene's diagonal, far below facingAway's own 1e-5 relative
// margin, so this never drops a pair the kernel would keep.
bool PairLoop::clusterFacesAway(const ClusterNode& a, const ClusterNode& b) const {
    const double margin = 1e-9 * diagonal_;
    const auto behind = [&](const ClusterNode& plane, const ClusterNode& other) {
        const Vec3d& normal = mesh_.normals[plane.begin];
        const double offset = dot(normal, mesh_.positions[mesh_.patches[plane.begin][0]]);
        for (const Vec3d& v : clusters_.outline(other)) {
            if (dot(normal, v) - offset > margin) return false;
        }
        return true;
    };
    return behind(a, b) || behind(b, a);
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

bool PairLoop::covered(const ClusterNode& a, const ClusterNode& b, const uint32_t* blockers,
                       std::size_t count) const {
    for (std::size_t k = 0; k < count; ++k) {
        const uint32_t face = clusters_.blockerFace[blockers[k]];
        if (face != kNoFace &&
            faceCoversShaft(clusters_.faces[face], clusters_.outline(a), clusters_.outline(b),
                            coverMargin_)) {
            return true;
        }
    }
    return false;
}

// Shaft refinement of the node pair (nodeA, nodeB) whose blockers are scratch.blockers[lo, hi):
// an empty list makes every pair clear, a covering solid face makes every pair hidden, a small
// node pair is traced; otherwise both nodes are halved and each of the four sub-shafts filters
// the list (a sub-shaft lies inside its parent, so no blocker is missed).
void PairLoop::refine(uint32_t nodeA, uint32_t nodeB, std::size_t lo, std::size_t hi, int depth,
                      const ClusterNode& rowCluster, const ClusterNode& columnCluster,
                      ThreadScratch& scratch, FormFactorStats& stats) const {
    const ClusterNode& a = clusters_.nodes[nodeA];
    const ClusterNode& b = clusters_.nodes[nodeB];
    const auto mark = [&](Visibility v) {
        const uint32_t width = columnCluster.end - columnCluster.begin;
        for (uint32_t i = a.begin; i < a.end; ++i) {
            Visibility* row = scratch.visibility.data() + std::size_t(i - rowCluster.begin) * width;
            std::fill(row + (b.begin - columnCluster.begin), row + (b.end - columnCluster.begin),
                      v);
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
    if (uint64_t(a.end - a.begin) * (b.end - b.begin) <= kMinRefinePairs) {
        mark(Visibility::Trace);
        return;
    }
    // Halve both nodes (or the one that still can be): four (or two) smaller shafts.
    const uint32_t childrenA[2] = {a.firstChild != 0 ? a.firstChild : nodeA, a.firstChild + 1};
    const uint32_t childrenB[2] = {b.firstChild != 0 ? b.firstChild : nodeB, b.firstChild + 1};
    const int countA = a.firstChild != 0 ? 2 : 1;
    const int countB = b.firstChild != 0 ? 2 : 1;
    for (int x = 0; x < countA; ++x) {
        for (int y = 0; y < countB; ++y) {
            const ClusterNode& ca = clusters_.nodes[childrenA[x]];
            const ClusterNode& cb = clusters_.nodes[childrenB[y]];
            const std::size_t childLo = scratch.blockers.size();
            Shaft& shaft = scratch.shaft(depth + 1);
            ++stats.shaftsBuilt;
            const bool valid =
                shaft.build(clusters_.outline(ca), clusters_.outline(cb), tolerance_);
            for (std::size_t k = lo; k < hi; ++k) {
                const uint32_t blocker = scratch.blockers[k];
                if (!valid || !shaft.excludesPolygon(clusters_.blockers[blocker])) {
                    scratch.blockers.push_back(blocker);
                }
            }
            refine(childrenA[x], childrenB[y], childLo, scratch.blockers.size(), depth + 1,
                   rowCluster, columnCluster, scratch, stats);
            scratch.blockers.resize(childLo);
        }
    }
}

void PairLoop::tracePending(ThreadScratch& scratch, FormFactorStats& stats) {
    if (scratch.pending.empty()) return;
    const int k = settings_.raysPerPair;
    scratch.segments.resize(scratch.pending.size() * std::size_t(k));
    scratch.blocked.resize(scratch.segments.size());
    for (std::size_t p = 0; p < scratch.pending.size(); ++p) {
        const PendingPair& pair = scratch.pending[p];
        shadowSegments(shared::pairSeed(pair.i, pair.j, seed_), k, geometry_[pair.i],
                       geometry_[pair.j], endClearance_, scratch.segments, p * k);
    }
    rays_.occluded(scratch.segments, scratch.blocked);
    std::size_t s = 0;
    for (const PendingPair& pair : scratch.pending) {
        int open = 0;
        for (int r = 0; r < k; ++r, ++s)
            open += scratch.blocked[s] == 0 ? 1 : 0;
        const float factor = open > 0 ? unoccludedFactor(pair.i, pair.j) : 0.0f;
        setPair(pair.slot, pair.mirrorSlot, pair.i, pair.j,
                static_cast<float>(double(factor) * double(open) / double(k)));
        stats.zeroFactor += open > 0 && factor == 0.0f ? 1 : 0;
        stats.hiddenPairs += open == 0 ? 1 : 0;
        stats.openPairs += open == k ? 1 : 0;
    }
    stats.tracedPairs += scratch.pending.size();
    stats.raysCast += scratch.segments.size();
    scratch.pending.clear();
}

// One row block: its clusters in order, each against every cluster from itself on. Upper entries
// go to each row's running cursor; mirrored entries F_ji = F_ij A_i / A_j go to row j at the
// block's column base plus a per-column cursor, so every row ends up in ascending column order
// with no pass over the matrix afterwards.
void PairLoop::computeBlock(std::size_t block, ThreadScratch& scratch, FormFactorStats& stats,
                            Progress& progress) {
    const uint32_t firstRow = clusters_.cluster(blockCluster_[block]).begin;
    const uint32_t endRow = clusters_.cluster(blockCluster_[block + 1] - 1).end;
    scratch.cursor.resize(endRow - firstRow);
    for (uint32_t i = firstRow; i < endRow; ++i)
        scratch.cursor[i - firstRow] = matrix_.rowOffsets[i] + lowerCount_[i];
    scratch.columnCursor.assign(n_, 0);
    scratch.firstRow = firstRow;
    for (std::size_t a = blockCluster_[block]; a < blockCluster_[block + 1]; ++a)
        computeCluster(block, a, scratch, stats, progress);
}

void PairLoop::computeCluster(std::size_t block, std::size_t a, ThreadScratch& scratch,
                              FormFactorStats& stats, Progress& progress) {
    const ClusterNode& rowCluster = clusters_.cluster(a);
    const uint32_t* columnBase = columnBase_.data() + block * n_;
    const bool visibility = settings_.raysPerPair > 0;
    for (std::size_t b = a; b < clusters_.clusterCount(); ++b) {
        const ClusterNode& columnCluster = clusters_.cluster(b);
        const uint32_t width = columnCluster.end - columnCluster.begin;
        const uint64_t blockPairs = a == b ? uint64_t(width) * (width - 1) / 2
                                           : uint64_t(rowCluster.end - rowCluster.begin) * width;
        uint64_t blockCandidates = 0;
        for (uint32_t i = rowCluster.begin; i < rowCluster.end; ++i) {
            for (uint32_t j = std::max(columnCluster.begin, i + 1); j < columnCluster.end; ++j)
                blockCandidates += candidates_.test(i, j) ? 1 : 0;
        }
        stats.facingAway += blockPairs - blockCandidates;
        if (blockCandidates == 0) {
            progress.advance(blockPairs);
            continue;
        }
        // Classify the block's pairs: shaft of the cluster pair, then refinement. Pairs inside
        // one cluster (nearly coplanar) are simply traced.
        scratch.visibility.assign(std::size_t(rowCluster.end - rowCluster.begin) * width,
                                  visibility ? Visibility::Trace : Visibility::ClearCluster);
        if (visibility && settings_.shaftCulling && a != b) {
            Shaft& shaft = scratch.shaft(0);
            ++stats.shaftsBuilt;
            if (shaft.build(clusters_.outline(rowCluster), clusters_.outline(columnCluster),
                            tolerance_)) {
                scratch.blockers.clear();
                bvh_.query(shaft, clusterPlane(rowCluster), clusterPlane(columnCluster), tolerance_,
                           scratch.blockers);
                refine(clusters_.clusterRoot[a], clusters_.clusterRoot[b], 0,
                       scratch.blockers.size(), 0, rowCluster, columnCluster, scratch, stats);
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
                    continue;
                }
                if (v == Visibility::Trace) {
                    // The factor waits for the rays: a pair they find fully hidden needs none.
                    scratch.pending.push_back({slot, mirrorSlot, i, j});
                    if (scratch.pending.size() * std::size_t(settings_.raysPerPair) >=
                        kMaxPendingSegments) {
                        tracePending(scratch, stats);
                    }
                    continue;
                }
                const float factor = unoccludedFactor(i, j);
                setPair(slot, mirrorSlot, i, j, factor);
                if (factor == 0.0f) {
                    ++stats.zeroFactor;
                } else if (v == Visibility::ClearCluster) {
                    stats.clearClusterShafts += visibility ? 1 : 0;
                } else {
                    ++stats.clearPairShafts;
                }
            }
        }
        tracePending(scratch, stats);
        progress.advance(blockPairs);
    }
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
    stats_.workBytes = formFactorWorkBytes(n_, candidatePairs);
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
    matrix_.columns.resize(stats_.slots);
    matrix_.values.resize(stats_.slots);

    const auto pairStart = Clock::now();
    {
        Progress progress("view factors", stats_.pairs, "pairs",
                          settings_.progress && progressEnabledByDefault(), settings_.onProgress);
        tbb::enumerable_thread_specific<ThreadScratch> scratch;
        std::mutex statsMutex;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blockCluster_.size() - 1, 1),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              FormFactorStats local;
                              for (std::size_t block = range.begin(); block != range.end();
                                   ++block) {
                                  if (isCancelled(settings_.cancel)) break;
                                  computeBlock(block, scratch.local(), local, progress);
                              }
                              std::lock_guard<std::mutex> lock(statsMutex);
                              addStats(stats_, local);
                          });
    }
    stats_.pairSeconds = secondsSince(pairStart);
    if (isCancelled(settings_.cancel)) return Error{kInterruptedMessage};

    const auto compactStart = Clock::now();
    candidates_.words = {};
    columnBase_ = {};
    dropZeros(matrix_);
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

uint64_t formFactorWorkBytes(uint64_t patchCount, uint64_t candidatePairs) {
    const uint64_t n = patchCount;
    const uint64_t rowBlocks = n / kMinRowBlockRows + 1;
    const uint64_t threads = std::max(1, tbb::this_task_arena::max_concurrency());
    return sparseMatrixBytes(n, 2 * candidatePairs) + CandidateBitmap::bytes(n) +
        4 * n * rowBlocks + 4 * n * (2 + threads);
}

Expected<FormFactorResult> computeFormFactors(const PatchMesh& mesh,
                                              const FormFactorSettings& settings,
                                              const RayCaster& rays) {
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
        if (settings.method == FormFactorMethod::Stochastic) {
            return computeStochastic(mesh, settings, rays);
        }
        PairLoop loop(mesh, settings, rays);
        return loop.run();
    });
}

}  // namespace daisy
