// The driver's candidate pass: the row blocks, the pairs that do not face away (per cluster
// pair when its planes decide it, else per patch pair) and the exact row sizes of the CSR.
#include "radiosity/form_factors_pair_loop.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "shared/formfactor.h"

namespace daisy::detail {

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

}  // namespace daisy::detail
