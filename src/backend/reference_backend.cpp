// The reference backend (DESIGN.md section 8): the shared pair kernel (shared/pair_kernel.h) run
// on the CPU over our flat BVH (raycast/flat_bvh.h), one TBB task per chunk of pairs. It is the
// oracle the GPU backends are checked against: the same source, no ray caster, the same driver as
// every backend (radiosity/form_factors.h); with shaftCulling off it traces every candidate.
// Every entry is a pure function of (pair, settings), so F is the same for any thread count.
// The stochastic method is refused (buildFromPairBatches): it is not a per-pair kernel.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "backend/backend.h"
#include "backend/pair_batches.h"
#include "radiosity/form_factors_internal.h"
#include "radiosity/pair_evaluator.h"
#include "raycast/flat_bvh.h"
#include "raycast/ray_caster.h"
#include "shared/pair_kernel.h"

namespace daisy {
namespace {

static_assert(DAISY_SEGMENT_MARGIN == RayCaster::kSegmentMargin,
              "shadow segments must span the same t range as the cpu backend's");

// Pairs handed to the evaluator at once: 64 Ki pairs (1 MiB of pairs and results) keep every
// worker busy while the driver's CSR scatter between batches stays short.
constexpr std::size_t kBatchPairs = std::size_t(1) << 16;

class ReferenceBackend final : public Backend {
public:
    std::string name() const override { return "reference"; }

    Expected<FormFactorResult> buildFormFactors(const PatchMesh& mesh,
                                                const FormFactorSettings& settings) override {
        Expected<FlatBvh> bvh = buildFlatBvh(mesh);
        if (!bvh) return bvh.error();
        const std::vector<shared::PatchGeometry> patches = kernelPatches(mesh);
        const shared::BvhNodeBuffer nodes{bvh->nodes.data()};
        const shared::BvhTriangleBuffer triangles{bvh->triangles.data()};
        const int method = detail::methodConstant(settings.method);
        const int level = settings.quadratureLevel;
        const uint32_t seed = detail::seed32(settings.seed);
        const PairKernelBatch evaluate = [&](std::span<const shared::PairIndex> pairs, int rays,
                                             std::span<shared::PairFactors> out) -> Expected<void> {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pairs.size(), 64),
                              [&](const tbb::blocked_range<std::size_t>& range) {
                                  for (std::size_t k = range.begin(); k != range.end(); ++k) {
                                      const uint32_t i = pairs[k].i;
                                      const uint32_t j = pairs[k].j;
                                      out[k] = shared::pairEntry(
                                          i, j, patches[i], patches[j], method, level, rays, seed,
                                          kEndClearanceRelative, nodes, triangles);
                                  }
                              });
            return {};
        };
        return buildFromPairBatches(mesh, settings, "reference", kBatchPairs, evaluate);
    }
};

}  // namespace

std::unique_ptr<Backend> makeReferenceBackend() {
    return std::make_unique<ReferenceBackend>();
}

}  // namespace daisy
