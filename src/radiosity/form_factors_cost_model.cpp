// The driver's cost model: the costs of rays, shafts and shaft tests measured on this scene and
// backend before the pair loop, and corrected after each wave from what the wave took.
#include "radiosity/form_factors_pair_loop.h"

#include <tbb/task_arena.h>

#include <algorithm>

#include "core/timer.h"
#include "shared/rng.h"

namespace daisy::detail {

// The cost model's constants, measured on this scene and backend: the seconds of
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
    std::vector<PairFactors> out(pairs.size());
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
            const auto open = std::count_if(out.begin(), out.end(),
                                            [](const PairFactors& f) { return f.fij > 0; });
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

}  // namespace daisy::detail
