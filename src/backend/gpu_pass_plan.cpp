#include "backend/gpu_pass_plan.h"

#include <algorithm>
#include <utility>

#include "core/strings.h"
#include "core/timer.h"
#include "shared/config.h"

namespace daisy {

using shared::PairFactors;
using shared::PairIndex;

GpuPassEvaluator::GpuPassEvaluator(std::string name, std::size_t batchPairs, int method,
                                   PairKernelPasses& passes, double segmentNs)
    : name_(std::move(name)),
      batchPairs_(std::max<std::size_t>(1, batchPairs)),
      method_(method),
      passes_(passes),
      segmentNs_(segmentNs) {}

Expected<void> GpuPassEvaluator::factors(std::span<const PairIndex> pairs,
                                         std::span<PairFactors> out) {
    stats_.factorPairs += pairs.size();
    if (method_ != DAISY_METHOD_HYBRID)
        return passes_.runPass(pairs, DAISY_PAIR_MODE_FACTORS, 0, out);
    Expected<void> done = passes_.runPass(pairs, DAISY_PAIR_MODE_FAR_FIELD, 0, out);
    if (!done) return done;
    near_.clear();
    nearSlot_.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (out[k].fij == DAISY_FF_NEEDS_NEAR_CELLS) {
            near_.push_back(pairs[k]);
            nearSlot_.push_back(uint32_t(k));
        }
    }
    stats_.nearPairs += near_.size();
    if (near_.empty()) return {};
    nearFactors_.resize(near_.size());
    done = passes_.runPass(near_, DAISY_PAIR_MODE_FACTORS, 0, nearFactors_);
    if (!done) return done;
    for (std::size_t k = 0; k < near_.size(); ++k)
        out[nearSlot_[k]] = nearFactors_[k];
    return {};
}

Expected<void> GpuPassEvaluator::evaluate(std::span<const PairIndex> pairs, int rays,
                                          std::span<PairFactors> out) {
    if (rays == 0) {
        const auto start = Clock::now();
        Expected<void> done = factors(pairs, out);
        stats_.factorSeconds += secondsSince(start);
        return done;
    }
    auto start = Clock::now();
    visibility_.resize(pairs.size());
    Expected<void> done = passes_.runPass(pairs, DAISY_PAIR_MODE_VISIBILITY, rays, visibility_);
    stats_.visibilitySeconds += secondsSince(start);
    if (!done) return done;
    open_.clear();
    openSlot_.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        out[k] = PairFactors{0.0f, 0.0f};
        if (visibility_[k].fij > 0.0f) {
            open_.push_back(pairs[k]);
            openSlot_.push_back(uint32_t(k));
        }
    }
    stats_.tracedPairs += pairs.size();
    stats_.openPairs += open_.size();
    if (open_.empty()) return {};
    start = Clock::now();
    openFactors_.resize(open_.size());
    done = factors(open_, openFactors_);
    if (done) {
        for (std::size_t k = 0; k < open_.size(); ++k) {
            const float v = visibility_[openSlot_[k]].fij;
            out[openSlot_[k]] = PairFactors{openFactors_[k].fij * v, openFactors_[k].fji * v};
        }
    }
    stats_.factorSeconds += secondsSince(start);
    return done;
}

std::string GpuPassEvaluator::summary() const {
    return concat(name_, ": ", formatCount(stats_.tracedPairs), " traced pairs' visibility in ",
                  formatDuration(stats_.visibilitySeconds), ", the factors of ",
                  formatCount(stats_.openPairs), " of them and of every clear pair in ",
                  formatDuration(stats_.factorSeconds), " (", formatCount(stats_.nearPairs),
                  " of those ", formatCount(stats_.factorPairs),
                  " with a near cell, whose factors are the whole hybrid kernel's; the others' "
                  "without its refinement)");
}

uint64_t pairWork(const FormFactorSettings& settings) {
    const uint64_t points = settings.method == FormFactorMethod::Nusselt
        ? 1
        : uint64_t(1) << (2 * std::clamp(settings.quadratureLevel, 0, 15));
    return uint64_t(std::max(settings.raysPerPair, 0)) + points;
}

uint64_t launchPairsForWork(uint64_t workLimit, uint64_t pairWork, uint64_t groupSize) {
    const uint64_t group = std::max<uint64_t>(groupSize, 1);
    return std::max(group, workLimit / std::max<uint64_t>(pairWork, 1) / group * group);
}

}  // namespace daisy
