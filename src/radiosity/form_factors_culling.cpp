// The driver's per-block classification: each cluster pair's shaft, then its refinement into
// smaller node pairs, decides which candidate pairs are clear (V = 1), covered (V = 0) or
// traced, and where both entries of each go in the CSR.
#include "radiosity/form_factors_pair_loop.h"

#include <algorithm>

#include "raycast/ray_caster.h"

namespace daisy::detail {

bool PairLoop::covered(const ClusterNode& a, const ClusterNode& b, const uint32_t* blockers,
                       std::size_t count, BlockOutput& out) const {
    const Bounds3d bounds = boundsOf(clusters_.outline(a), clusters_.outline(b));
    // Segments stop kSegmentMargin of their length short of each end: a covering face must
    // clear that much of the shaft's size too.
    const double margin =
        std::max(toleranceOf(bounds), 4.0 * RayCaster::kSegmentMargin * bounds.diagonal());
    for (std::size_t k = 0; k < count; ++k) {
        const uint32_t face = clusters_.blockerFace[blockers[k]];
        out.cullNs += face != kNoFace ? kTestNs : 0;
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
    if (covered(a, b, scratch.blockers.data() + lo, hi - lo, out)) {
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
    const double benefit = pairs <= kSmallNodePairs ? kSmallRefineBenefit : kRefineBenefit;
    if (costModel_ && splitCost(countA * countB, hi - lo) > benefit * traceCost(pairs)) {
        ++stats.costStoppedRefinements;
        mark(Visibility::Trace);
        return;
    }
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
            out.cullNs += kShaftNs + double(hi - lo) * kTestNs;
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
        // rays the cost model prices below one shaft query. Every choice here depends on the
        // geometry and on the gate, which changes only between waves.
        scratch.visibility.assign(std::size_t(rowCluster.end - rowCluster.begin) * width,
                                  visibility ? Visibility::Trace : Visibility::ClearCluster);
        if (culling() && a != b) {
            if (costModel_ &&
                ((!gateOpen_ && (a + b) % kGateSample != 0) ||
                 traceCost(blockCandidates) < stats_.costQueryNs)) {
                ++stats.costTracedClusterPairs;
            } else {
                ++stats.culledClusterPairs;
                Shaft& shaft = scratch.shaft(0);
                ++stats.shaftsBuilt;
                const double tolerance = toleranceOf(
                    boundsOf(clusters_.outline(rowCluster), clusters_.outline(columnCluster)));
                BlockerQueryWork work;
                if (shaft.build(clusters_.outline(rowCluster), clusters_.outline(columnCluster),
                                tolerance)) {
                    scratch.blockers.clear();
                    bvh_.query(shaft, clusterPlane(rowCluster), clusterPlane(columnCluster),
                               tolerance, scratch.blockers, work);
                    refine(clusters_.clusterRoot[a], clusters_.clusterRoot[b], 0,
                           scratch.blockers.size(), 0, rowCluster, columnCluster, scratch, out);
                }
                out.cullNs += queryNs(work);
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

}  // namespace daisy::detail
