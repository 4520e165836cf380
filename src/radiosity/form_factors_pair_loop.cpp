// The driver's pair loop: waves of row blocks classified in parallel, then their clear and traced
// pairs evaluated by the backend in its batches, both entries stored, and at the end the stored
// zeros dropped and the row sums capped.
#include "radiosity/form_factors_pair_loop.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/memory.h"
#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"

namespace daisy::detail {

// Evaluates the wave's clear (traced = false: no rays) or traced pairs in the backend's batches,
// in block order, and stores both entries of each.
Expected<void> PairLoop::evaluate(const std::vector<BlockOutput>& outputs, bool traced) {
    const int rays = traced ? settings_.raysPerPair : 0;
    std::vector<const PendingPair*>& owners = owners_;
    owners.clear();
    const auto flush = [&]() -> Expected<void> {
        if (batch_.empty()) return {};
        if (isCancelled(settings_.cancel)) return Error{kInterruptedMessage};
        results_.assign(batch_.size(), PairFactors{0.0f, 0.0f});
        Expected<void> done = evaluator_.evaluate(batch_, rays, results_);
        if (!done) return withContext(done.error(), concat("backend '", evaluator_.name(), "'"));
        for (std::size_t k = 0; k < batch_.size(); ++k) {
            const PendingPair& pair = *owners[k];
            const float fij = results_[k].fij;
            if (!(std::isfinite(fij) && fij >= 0.0f)) {
                return Error{concat("backend '", evaluator_.name(), "' returned F_", pair.i, ",",
                                    pair.j, " = ", fij, " (not a finite factor >= 0)")};
            }
            setPair(pair.slot, pair.mirrorSlot, pair.i, pair.j, fij);
            if (fij == 0.0f) (traced ? stats_.hiddenPairs : stats_.zeroFactor) += 1;
        }
        if (traced) {
            stats_.tracedPairs += batch_.size();
            stats_.raysCast += batch_.size() * uint64_t(rays);
        }
        batch_.clear();
        owners.clear();
        return {};
    };
    for (const BlockOutput& out : outputs) {
        for (const PendingPair& pair : traced ? out.trace : out.clear) {
            batch_.push_back({pair.i, pair.j});
            owners.push_back(&pair);
            if (batch_.size() == batchPairs_) {
                Expected<void> done = flush();
                if (!done) return done;
            }
        }
    }
    return flush();
}

Expected<FormFactorResult> PairLoop::run() {
    const auto start = Clock::now();
    stats_.patches = n_;
    stats_.pairs = n_ < 2 ? 0 : uint64_t(n_) * (n_ - 1) / 2;
    stats_.clusters = clusters_.clusterCount();

    buildRowBlocks();
    countCandidates();
    uint64_t candidatePairs = 0;
    for (uint32_t i = 0; i < n_; ++i)
        candidatePairs += upperCount_[i];
    stats_.countSeconds = secondsSince(start);
    stats_.slots = 2 * candidatePairs;
    uint64_t blockRows = 2 * kMaxClusterSize;
    for (std::size_t b = 0; b + 1 < blockCluster_.size(); ++b) {
        blockRows = std::max<uint64_t>(blockRows,
                                       clusters_.cluster(blockCluster_[b + 1] - 1).end -
                                           clusters_.cluster(blockCluster_[b]).begin);
    }
    stats_.workBytes = formFactorWorkBytes(n_, candidatePairs, blockRows);
    if (settings_.maxMemoryBytes > 0 && stats_.workBytes > settings_.maxMemoryBytes) {
        return Error{concat("the view-factor matrix needs ",
                            formatBytes(static_cast<double>(stats_.workBytes)), " for ",
                            formatCount(candidatePairs), " facing pairs of ", formatCount(n_),
                            " patches, more than --max-memory ",
                            formatBytes(static_cast<double>(settings_.maxMemoryBytes)),
                            "; use fewer patches (a larger --subdivide) or raise --max-memory")};
    }

    matrix_.size = n_;
    matrix_.rowOffsets.assign(std::size_t(n_) + 1, 0);
    for (uint32_t i = 0; i < n_; ++i)
        matrix_.rowOffsets[i + 1] = matrix_.rowOffsets[i] + lowerCount_[i] + upperCount_[i];
    resizeOnHugePages(matrix_.columns, stats_.slots);
    resizeOnHugePages(matrix_.values, stats_.slots);

    const auto pairStart = Clock::now();
    calibrate();
    {
        Progress progress("view factors", stats_.pairs, "pairs",
                          settings_.progress && progressEnabledByDefault(), settings_.onProgress);
        tbb::enumerable_thread_specific<ThreadScratch> scratch;
        std::vector<BlockOutput> outputs;
        const std::size_t blockCount = blockCluster_.size() - 1;
        for (std::size_t first = 0; first < blockCount;) {
            if (isCancelled(settings_.cancel)) return Error{kInterruptedMessage};
            // A wave: blocks until about kWavePairs candidates, and at least kMinWaveBlocks
            // blocks (a block is classified by one thread: the large clusters of scattered runs
            // would otherwise leave the other threads idle); the same on any machine.
            std::size_t last = first;
            uint64_t wave = 0;
            while (last < blockCount && (last - first < kMinWaveBlocks || wave < kWavePairs)) {
                const uint32_t begin = clusters_.cluster(blockCluster_[last]).begin;
                const uint32_t end = clusters_.cluster(blockCluster_[last + 1] - 1).end;
                for (uint32_t i = begin; i < end; ++i)
                    wave += upperCount_[i];
                ++last;
            }
            outputs.resize(last - first);
            for (BlockOutput& out : outputs)
                out.reset();
            tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last, 1),
                              [&](const tbb::blocked_range<std::size_t>& range) {
                                  for (std::size_t block = range.begin(); block != range.end();
                                       ++block) {
                                      if (isCancelled(settings_.cancel)) break;
                                      computeBlock(block, scratch.local(), outputs[block - first]);
                                  }
                              });
            if (isCancelled(settings_.cancel)) return Error{kInterruptedMessage};
            for (bool traced : {false, true}) {
                Expected<void> done = evaluate(outputs, traced);
                if (!done) return done.error();
            }
            uint64_t pairs = 0;
            for (const BlockOutput& out : outputs) {
                addStats(stats_, out.stats);
                pairs += out.pairs;
            }
            if (costModel_) updateGate(outputs);
            progress.advance(pairs);
            first = last;
        }
    }
    stats_.pairSeconds = secondsSince(pairStart);
    if (isCancelled(settings_.cancel)) return Error{kInterruptedMessage};

    const auto compactStart = Clock::now();
    candidates_.words = {};
    columnBase_ = {};
    dropZeros(matrix_);
    if (settings_.raysPerPair > 0) {
        const RowSumCap cap = capRowSums(matrix_);
        stats_.rowsCapped = cap.rowsCapped;
        stats_.largestRowSum = cap.largestRowSum;
    }
    stats_.compactSeconds = secondsSince(compactStart);
    stats_.nonzeros = matrix_.nonzeroCount();
    stats_.totalSeconds = secondsSince(start);
    return FormFactorResult{std::move(matrix_), stats_};
}

}  // namespace daisy::detail
