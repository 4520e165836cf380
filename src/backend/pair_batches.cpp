#include "backend/pair_batches.h"

#include <algorithm>
#include <string>
#include <vector>

#include "radiosity/form_factors_internal.h"
#include "radiosity/pair_evaluator.h"

namespace daisy {
namespace {

using shared::PairFactors;
using shared::PairIndex;

// A pair-kernel backend as the driver's PairEvaluator: F_ij of each pair's kernel result.
class KernelEvaluator final : public PairEvaluator {
public:
    KernelEvaluator(const char* name, std::size_t batchPairs, const PairKernelBatch& evaluate)
        : name_(name), batchPairs_(std::max<std::size_t>(1, batchPairs)), evaluate_(evaluate) {}

    std::string name() const override { return name_; }
    std::size_t batchPairs() const override { return batchPairs_; }

    Expected<void> evaluate(std::span<const PairIndex> pairs, int rays,
                            std::span<float> fij) override {
        results_.assign(pairs.size(), PairFactors{0.0f, 0.0f});
        Expected<void> done = evaluate_(pairs, rays, results_);
        if (!done) return done;
        for (std::size_t k = 0; k < pairs.size(); ++k)
            fij[k] = results_[k].fij;
        return {};
    }

private:
    std::string name_;
    std::size_t batchPairs_;
    const PairKernelBatch& evaluate_;
    std::vector<PairFactors> results_;
};

}  // namespace

std::vector<shared::PatchGeometry> kernelPatches(const PatchMesh& mesh) {
    return detail::kernelGeometry(mesh);
}

uint64_t pairWork(const FormFactorSettings& settings) {
    const uint64_t points = settings.method == FormFactorMethod::Nusselt
        ? 1
        : uint64_t(1) << (2 * std::clamp(settings.quadratureLevel, 0, 15));
    return uint64_t(std::max(settings.raysPerPair, 0)) + points;
}

Expected<FormFactorResult> buildFromPairBatches(const PatchMesh& mesh,
                                                const FormFactorSettings& settings,
                                                const char* backendName, std::size_t batchPairs,
                                                const PairKernelBatch& evaluate) {
    KernelEvaluator evaluator(backendName, batchPairs, evaluate);
    return computeFormFactors(mesh, settings, evaluator);
}

}  // namespace daisy
