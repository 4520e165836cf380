// The form-factor driver's entry points (radiosity/form_factors.h): method names, the memory
// estimate, and computeFormFactors, which checks the settings and runs the pair loop
// (form_factors_pair_loop.h) in the caller's thread count, or the stochastic method
// (stochastic_form_factors.h).
#include "radiosity/form_factors.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <memory>

#include "core/strings.h"
#include "radiosity/form_factors_pair_loop.h"
#include "radiosity/ray_pair_evaluator.h"
#include "radiosity/stochastic_form_factors.h"
#include "shared/config.h"

namespace daisy {

using detail::CandidateBitmap;
using detail::computeStochastic;
using detail::kMinRowBlockRows;
using detail::kMinWaveBlocks;
using detail::kWavePairs;
using detail::PairLoop;
using detail::PendingPair;
using shared::PairFactors;
using shared::PairIndex;

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

uint64_t formFactorWorkBytes(uint64_t patchCount, uint64_t candidatePairs, uint64_t blockRows) {
    const uint64_t n = patchCount;
    const uint64_t rowBlocks = n / kMinRowBlockRows + 1;
    const uint64_t threads = std::max(1, tbb::this_task_arena::max_concurrency());
    // A wave's pending pairs (at most kWavePairs plus one block, or kMinWaveBlocks blocks: each
    // of at most blockRows rows) and one batch of pairs with their results.
    const uint64_t wave = std::min(
        candidatePairs, std::max(kWavePairs + blockRows * n, kMinWaveBlocks * blockRows * n));
    const uint64_t batch = std::min(candidatePairs, kWavePairs);
    return sparseMatrixBytes(n, 2 * candidatePairs) + CandidateBitmap::bytes(n) +
        4 * n * rowBlocks + 4 * n * (2 + threads) + wave * sizeof(PendingPair) +
        batch * (sizeof(PairIndex) + sizeof(PairFactors) + sizeof(void*));
}

Expected<void> checkPairMethod(const FormFactorSettings& settings, const std::string& backend) {
    if (settings.method == FormFactorMethod::Stochastic) {
        return Error{concat("backend '", backend,
                            "' has no stochastic method (its rays are per patch, not per pair); "
                            "use --method hybrid, riemann or nusselt, or --backend cpu")};
    }
    return {};
}

Expected<FormFactorResult> computeFormFactors(const PatchMesh& mesh,
                                              const FormFactorSettings& settings,
                                              PairEvaluator& evaluator) {
    Expected<void> pairMethod = checkPairMethod(settings, evaluator.name());
    if (!pairMethod) return pairMethod.error();
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
        PairLoop loop(mesh, settings, evaluator);
        return loop.run();
    });
}

Expected<FormFactorResult> computeFormFactors(const PatchMesh& mesh,
                                              const FormFactorSettings& settings,
                                              const RayCaster& rays) {
    if (settings.method != FormFactorMethod::Stochastic) {
        const std::unique_ptr<PairEvaluator> evaluator = makeRayPairEvaluator(mesh, settings, rays);
        return computeFormFactors(mesh, settings, *evaluator);
    }
    if (settings.raysPerPair < 0 || settings.stochasticRays < 1) {
        return Error{"ray counts must be positive"};
    }
    if (mesh.patchCount() > UINT32_MAX - 1) return Error{"too many patches for 32-bit indices"};
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    return arena.execute([&]() { return computeStochastic(mesh, settings, rays); });
}

}  // namespace daisy
