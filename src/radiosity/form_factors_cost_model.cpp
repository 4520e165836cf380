// The driver's cost model: what a cluster pair's blocker query costs, estimated on this scene
// before the pair loop, and the gate updated after each wave. Every price is a fixed constant
// (form_factors_pair_loop.h, PairEvaluator::segmentNs) times work that was counted, never a
// timing: the model decides which pairs are culled and which traced, and a clear or covered
// shaft and the rays can differ on a few pairs (a segment trimmed short where a patch crosses
// the other's plane, one grazing an edge), so a choice that followed the machine's load would
// change F from run to run. It chooses how F is computed, and F is the same whatever it chooses
// on this scene and backend, for any thread count and load.
#include "radiosity/form_factors_pair_loop.h"

#include <algorithm>

#include "shared/rng.h"

namespace daisy::detail {

// The price of a cluster pair's shaft with its blocker query, on this scene: the mean of the
// counted work of up to 64 distinct cluster pairs spread over the matrix (drawn by hash, so the
// same every run) that face each other. The price of a segment is the backend's.
void PairLoop::calibrate() {
    const std::size_t clusterCount = clusters_.clusterCount();
    if (!culling() || !settings_.costModel || clusterCount < 2) return;
    stats_.costRayNs = evaluator_.segmentNs();
    stats_.costShaftNs = kShaftNs;
    stats_.costTestNs = kTestNs;
    std::vector<std::pair<std::size_t, std::size_t>> samples;
    for (uint32_t s = 0; s < 4096 && samples.size() < 64; ++s) {
        const std::size_t a = shared::pcgHash(2 * s + 1) % clusterCount;
        const std::size_t b = shared::pcgHash(2 * s + 2) % clusterCount;
        if (a == b) continue;
        const std::pair<std::size_t, std::size_t> pair{std::min(a, b), std::max(a, b)};
        if (std::find(samples.begin(), samples.end(), pair) != samples.end() ||
            clusterFacesAway(clusters_.cluster(pair.first), clusters_.cluster(pair.second))) {
            continue;
        }
        samples.push_back(pair);
    }
    Shaft shaft;
    std::vector<uint32_t> found;
    BlockerQueryWork work;
    for (const auto& [a, b] : samples) {
        const ClusterNode& p = clusters_.cluster(a);
        const ClusterNode& q = clusters_.cluster(b);
        const double tolerance = toleranceOf(boundsOf(clusters_.outline(p), clusters_.outline(q)));
        found.clear();
        if (shaft.build(clusters_.outline(p), clusters_.outline(q), tolerance))
            bvh_.query(shaft, clusterPlane(p), clusterPlane(q), tolerance, found, work);
    }
    const double count = double(std::max<std::size_t>(1, samples.size()));
    stats_.costQueryNs = kShaftNs + double(work.nodes) / count * kQueryNodeNs +
        double(work.blockers) / count * kQueryBlockerNs;
    costModel_ = true;
}

void PairLoop::updateGate(const std::vector<BlockOutput>& outputs) {
    for (const BlockOutput& out : outputs)
        stats_.costCullNs += out.cullNs;
    // What culling saved: the rays of every pair it decided (clear or covered; the stats are
    // cumulative, this wave's already added).
    const uint64_t resolved =
        stats_.clearClusterShafts + stats_.clearPairShafts + stats_.coveredPairs;
    stats_.costSavedNs = traceCost(resolved);
    gateOpen_ = stats_.costCullNs <= stats_.costSavedNs;
    stats_.costGateClosedWaves += gateOpen_ ? 0 : 1;
}

}  // namespace daisy::detail
