// F is a function of the geometry, the settings and the backend alone: the same bytes for any
// thread count and whatever the machine's load. The cost model chooses which pairs are culled
// and which traced, and the two can give different values for a few pairs (a segment trimmed
// short where a patch crosses the other's plane; docs/formfactors.md), so its choices must not
// follow timings: here the rays are made several times slower than they are (what a loaded
// machine does to a timed model), and neither the choices nor F may change.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <memory>
#include <string>

#include "radiosity/form_factors.h"
#include "radiosity/ray_pair_evaluator.h"
#include "raycast/ray_caster.h"
#include "scene/load_scene.h"
#include "test_util.h"

namespace daisy {
namespace {

// The cpu backend's evaluator, with every traced segment made slower by `extraNs` (busy wait,
// as a loaded core would be).
class SlowedRays final : public PairEvaluator {
public:
    SlowedRays(PairEvaluator& inner, double extraNs) : inner_(inner), extraNs_(extraNs) {}
    std::string name() const override { return inner_.name(); }
    std::size_t batchPairs() const override { return inner_.batchPairs(); }
    double segmentNs() const override { return inner_.segmentNs(); }
    Expected<void> evaluate(std::span<const shared::PairIndex> pairs, int rays,
                            std::span<shared::PairFactors> out) override {
        const auto until = std::chrono::steady_clock::now() +
            std::chrono::nanoseconds(int64_t(extraNs_ * double(rays) * double(pairs.size())));
        while (std::chrono::steady_clock::now() < until) {
        }
        return inner_.evaluate(pairs, rays, out);
    }

private:
    PairEvaluator& inner_;
    double extraNs_;
};

FormFactorResult buildWith(const PatchMesh& mesh, int threads, double extraNs) {
    FormFactorSettings settings;
    settings.progress = false;
    settings.threads = threads;
    // The cpu backend's ray caster.
    auto caster =
        makeRayCaster(mesh, {.packetMode = PacketMode::Stream, .watertightSegments = true});
    EXPECT_TRUE(caster.ok());
    const std::unique_ptr<PairEvaluator> evaluator = makeRayPairEvaluator(mesh, settings, **caster);
    SlowedRays slowed(*evaluator, extraNs);
    auto result = computeFormFactors(mesh, settings, slowed);
    EXPECT_TRUE(result.ok()) << (result.ok() ? "" : result.error().message);
    return std::move(*result);
}

void expectSameBytes(const SparseMatrix& a, const SparseMatrix& b, const std::string& what) {
    EXPECT_EQ(a.rowOffsets, b.rowOffsets) << what;
    EXPECT_EQ(a.columns, b.columns) << what;
    ASSERT_EQ(a.values.size(), b.values.size()) << what;
    EXPECT_EQ(std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(float)), 0)
        << what;
}

// The small black-light box of the benchmark family: the model culls most cluster pairs, traces
// some without culling and stops thousands of refinements, so its choices are exercised. One
// and two threads, and rays slowed by 500 ns a segment (about 4x their price) on one and two
// threads: the same choices, the same traced pairs, the same bytes.
TEST(FormFactorDeterminism, SameBytesForAnyThreadCountAndRaySpeed) {
    auto scene = loadScene(test::assetPath("scenes/formfactor_family/blacklight_small.gltf"));
    ASSERT_TRUE(scene.ok());
    auto mesh = buildPatchMesh(scene->mesh, 0);
    ASSERT_TRUE(mesh.ok());
    const FormFactorResult first = buildWith(*mesh, 1, 0);
    const FormFactorStats& s = first.stats;
    EXPECT_GT(s.culledClusterPairs, 0u);
    EXPECT_GT(s.costTracedClusterPairs, 0u);
    EXPECT_GT(s.costStoppedRefinements, 0u);
    EXPECT_GT(s.tracedPairs, 0u);
    for (const auto& [threads, extraNs] :
         {std::pair{2, 0.0}, std::pair{1, 500.0}, std::pair{2, 500.0}}) {
        const std::string what =
            std::to_string(threads) + " threads, +" + std::to_string(int(extraNs)) + " ns a ray";
        const FormFactorResult other = buildWith(*mesh, threads, extraNs);
        EXPECT_EQ(other.stats.culledClusterPairs, s.culledClusterPairs) << what;
        EXPECT_EQ(other.stats.costTracedClusterPairs, s.costTracedClusterPairs) << what;
        EXPECT_EQ(other.stats.costStoppedRefinements, s.costStoppedRefinements) << what;
        EXPECT_EQ(other.stats.tracedPairs, s.tracedPairs) << what;
        EXPECT_EQ(other.stats.raysCast, s.raysCast) << what;
        expectSameBytes(first.matrix, other.matrix, what);
    }
}

}  // namespace
}  // namespace daisy
