#include "radiosity/ray_pair_evaluator.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

#include "radiosity/hybrid_far_field.h"
#include "radiosity/kernel_inputs.h"
#include "radiosity/visibility_samples.h"
#include "shared/formfactor.h"
#include "shared/rng.h"
#include "shared/visibility.h"

namespace daisy {
namespace {

using shared::PairFactors;
using shared::PairIndex;
using shared::PatchGeometry;

// One traced segment on the reference machine: Embree's packet, the watertight filter on its
// candidates, the sample streams and the pair's share of batching (124-150 ns measured on the
// family's scenes at K = 4, docs/performance.md).
constexpr double kSegmentNs = 140;

// Pairs one call takes: the driver's batches; each task traces at most kTaskSegments segments
// at once (1.5 MB of scratch a thread), so a large --rays cannot make the scratch grow.
constexpr std::size_t kBatchPairs = std::size_t(1) << 16;
constexpr std::size_t kTaskSegments = std::size_t(1) << 16;

struct Scratch {
    SegmentArrays segments;
    std::vector<uint8_t> blocked;
    std::vector<float> weights;  // each segment's kernel weight
    std::vector<PairIndex> openPairs;  // traced pairs some segment reaches
    std::vector<PairFactors> openFactors;  // their unoccluded factors
    FarFieldScratch farField;
};

class RayPairEvaluator final : public PairEvaluator {
public:
    RayPairEvaluator(const PatchMesh& mesh, const FormFactorSettings& settings,
                     const RayCaster& rays, float hybridTolerance)
        : geometry_(kernelPatches(mesh)),
          farField_(farFieldPatches(geometry_)),
          rays_(rays),
          method_(kernelMethod(settings.method)),
          level_(settings.quadratureLevel),
          seed_(kernelSeed(settings.seed)),
          hybridTolerance_(hybridTolerance) {}

    std::string name() const override { return "cpu"; }
    std::size_t batchPairs() const override { return kBatchPairs; }
    double segmentNs() const override { return kSegmentNs; }

    Expected<void> evaluate(std::span<const PairIndex> pairs, int rays,
                            std::span<PairFactors> out) override {
        const std::size_t grain =
            std::max<std::size_t>(1, kTaskSegments / std::size_t(std::max(rays, 1)));
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pairs.size(), std::min(grain, 256ul)),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              for (std::size_t k = range.begin(); k < range.end(); k += grain) {
                                  const std::size_t end = std::min(range.end(), k + grain);
                                  if (rays == 0) {
                                      candidateFactorsCpu(method_, level_, geometry_, farField_,
                                                          pairs.subspan(k, end - k), out.subspan(k),
                                                          scratch_.local().farField,
                                                          hybridTolerance_);
                                  } else {
                                      trace(pairs.subspan(k, end - k), rays, out.subspan(k));
                                  }
                              }
                          });
        return {};
    }

private:
    void trace(std::span<const PairIndex> pairs, int k, std::span<PairFactors> out) const {
        Scratch& scratch = scratch_.local();
        scratch.segments.resize(pairs.size() * std::size_t(k));
        scratch.blocked.resize(scratch.segments.size());
        scratch.weights.resize(scratch.segments.size());
        for (std::size_t p = 0; p < pairs.size(); ++p) {
            const PatchGeometry& gi = geometry_[pairs[p].i];
            const PatchGeometry& gj = geometry_[pairs[p].j];
            shadowSegments(shared::pairSeed(pairs[p].i, pairs[p].j, seed_), k, gi, gj,
                           shared::pairClearance(kEndClearanceRelative, gi, gj), scratch.segments,
                           p * std::size_t(k), scratch.weights.data() + p * std::size_t(k));
        }
        rays_.occluded(scratch.segments, scratch.blocked);
        // The unoccluded factors of the pairs some segment reaches, in one batch (the far field
        // of many pairs fills the SIMD lanes: radiosity/hybrid_far_field.h).
        scratch.openPairs.clear();
        for (std::size_t p = 0, s = 0; p < pairs.size(); ++p, s += std::size_t(k)) {
            if (std::find(&scratch.blocked[s], &scratch.blocked[s] + k, 0) !=
                &scratch.blocked[s] + k)
                scratch.openPairs.push_back(pairs[p]);
        }
        scratch.openFactors.resize(scratch.openPairs.size());
        candidateFactorsCpu(method_, level_, geometry_, farField_, scratch.openPairs,
                            scratch.openFactors, scratch.farField, hybridTolerance_);
        std::size_t s = 0;
        std::size_t next = 0;
        for (std::size_t p = 0; p < pairs.size(); ++p) {
            // shared::pairVisibility's sums, in its order, so V is bit-identical to the
            // pair-kernel backends'; F = Fu V in float, as shared::pairEntry.
            int open = 0;
            float seen = 0.0f, total = 0.0f;
            for (int r = 0; r < k; ++r, ++s) {
                const float w = scratch.weights[s];
                total += w;
                if (scratch.blocked[s] == 0) {
                    seen += w;
                    ++open;
                }
            }
            if (open == 0) {
                out[p] = PairFactors{0.0f, 0.0f};
                continue;
            }
            const float v = shared::kernelWeightedVisibility(seen, total, open, k);
            const PairFactors& f = scratch.openFactors[next++];
            out[p] = PairFactors{f.fij * v, f.fji * v};
        }
    }

    std::vector<PatchGeometry> geometry_;
    std::vector<FarFieldPatch> farField_;  // farFieldPatches(geometry_)
    const RayCaster& rays_;
    int method_;
    int level_;
    uint32_t seed_;
    float hybridTolerance_;
    mutable tbb::enumerable_thread_specific<Scratch> scratch_;
};

}  // namespace

std::unique_ptr<PairEvaluator> makeRayPairEvaluator(const PatchMesh& mesh,
                                                    const FormFactorSettings& settings,
                                                    const RayCaster& rays, float hybridTolerance) {
    return std::make_unique<RayPairEvaluator>(mesh, settings, rays, hybridTolerance);
}

}  // namespace daisy
