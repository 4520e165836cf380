// The reference backend (DESIGN.md section 8): the shared pair kernel (shared/pair_kernel.h) run
// on the CPU over our flat BVH (raycast/flat_bvh.h), one TBB task per chunk of pairs, as a
// PairEvaluator (radiosity/pair_evaluator.h) of the one driver. It is the oracle the GPU backends
// are checked against: the same source, no ray caster, the same driver as every backend
// (radiosity/form_factors.h); with shaftCulling off it traces every candidate. Every entry is a
// pure function of (pair, settings), so F is the same for any thread count. The driver refuses
// the stochastic method: it is not a per-pair kernel.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "backend/backend.h"
#include "radiosity/kernel_inputs.h"
#include "radiosity/pair_evaluator.h"
#include "raycast/flat_bvh.h"
#include "raycast/ray_caster.h"
#include "shared/pair_kernel.h"

namespace daisy {
namespace {

using shared::PairFactors;
using shared::PairIndex;

static_assert(DAISY_SEGMENT_MARGIN == RayCaster::kSegmentMargin,
              "shadow segments must span the same t range as the cpu backend's");

// Pairs handed to the evaluator at once: 64 Ki pairs (1 MiB of pairs and results) keep every
// worker busy while the driver's CSR scatter between batches stays short.
constexpr std::size_t kBatchPairs = std::size_t(1) << 16;
// One segment of shared::pairVisibility through the flat BVH, scalar, on the reference machine
// (docs/performance.md).
constexpr double kSegmentNs = 400;

// shared::pairEntry of each pair, in parallel over the pairs.
class ReferenceEvaluator final : public PairEvaluator {
public:
    ReferenceEvaluator(const PatchMesh& mesh, const FlatBvh& bvh,
                       const FormFactorSettings& settings)
        : patches_(kernelPatches(mesh)),
          nodes_{bvh.nodes.data()},
          triangles_{bvh.triangles.data()},
          kernel_(kernelSettings(settings)) {}

    std::string name() const override { return "reference"; }
    std::size_t batchPairs() const override { return kBatchPairs; }
    double segmentNs() const override { return kSegmentNs; }

    Expected<void> evaluate(std::span<const PairIndex> pairs, int rays,
                            std::span<PairFactors> out) override {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pairs.size(), 64),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              for (std::size_t k = range.begin(); k != range.end(); ++k) {
                                  const uint32_t i = pairs[k].i;
                                  const uint32_t j = pairs[k].j;
                                  out[k] = shared::pairEntry(
                                      i, j, patches_[i], patches_[j], kernel_.method, kernel_.level,
                                      rays, kernel_.seed, kernel_.clearanceRelative, nodes_,
                                      triangles_);
                              }
                          });
        return {};
    }

private:
    std::vector<shared::PatchGeometry> patches_;
    shared::BvhNodeBuffer nodes_;
    shared::BvhTriangleBuffer triangles_;
    KernelSettings kernel_;
};

class ReferenceBackend final : public Backend {
public:
    std::string name() const override { return "reference"; }

    Expected<FormFactorResult> buildFormFactors(const PatchMesh& mesh,
                                                const FormFactorSettings& settings) override {
        Expected<void> pairMethod = checkPairMethod(settings, name());
        if (!pairMethod) return pairMethod.error();
        Expected<FlatBvh> bvh = buildFlatBvh(mesh);
        if (!bvh) return bvh.error();
        ReferenceEvaluator evaluator(mesh, *bvh, settings);
        return computeFormFactors(mesh, settings, evaluator);
    }
};

}  // namespace

std::unique_ptr<Backend> makeReferenceBackend() {
    return std::make_unique<ReferenceBackend>();
}

}  // namespace daisy
