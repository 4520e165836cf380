#include "backend/pair_batches.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "geometry/bounds.h"
#include "radiosity/form_factors_internal.h"
#include "radiosity/sparse_matrix.h"
#include "shared/config.h"
#include "shared/formfactor.h"

namespace daisy {
namespace {

using shared::PairFactors;
using shared::PairIndex;
using shared::PatchGeometry;

// Shadow segments stop this fraction of the scene's diagonal short of their patches' planes:
// the cpu driver's kEndClearanceRelative (radiosity/form_factors.cpp), so every backend traces
// the same segments; backend_equivalence_test.cpp compares the matrices entry by entry.
constexpr double kEndClearanceRelative = 2e-6;

// The candidate pairs of rows [rowBegin, rowEnd) from column `column` of rowBegin on, appended
// to `batch` until it holds `capacity` pairs; returns where to resume (row, column).
struct Cursor {
    uint32_t row = 0;
    uint32_t column = 1;
};

Cursor nextBatch(const std::vector<PatchGeometry>& geometry, Cursor at, std::size_t capacity,
                 std::vector<PairIndex>& batch) {
    const uint32_t n = static_cast<uint32_t>(geometry.size());
    batch.clear();
    while (at.row + 1 < n) {
        for (; at.column < n; ++at.column) {
            if (batch.size() == capacity) return at;
            if (shared::facingAway(geometry[at.row], geometry[at.column])) continue;
            batch.push_back({at.row, at.column});
        }
        at.row += 1;
        at.column = at.row + 1;
    }
    return at;
}

// Bytes the build holds at its peak: the CSR with every candidate slot, the per-row counts and
// cursors, the kernel geometry and one batch of pairs with their results.
uint64_t pairBatchWorkBytes(uint64_t n, uint64_t candidatePairs, uint64_t batchPairs) {
    return sparseMatrixBytes(n, 2 * candidatePairs) + n * (4 + 4 + 8 + 8) +
        n * sizeof(PatchGeometry) + batchPairs * (sizeof(PairIndex) + sizeof(PairFactors));
}

Expected<FormFactorResult> build(const PatchMesh& mesh, const FormFactorSettings& settings,
                                 const char* backendName, std::size_t batchPairs,
                                 const PairEvaluator& evaluate) {
    const auto start = Clock::now();
    const uint32_t n = static_cast<uint32_t>(mesh.patchCount());
    const std::vector<PatchGeometry> geometry = kernelPatches(mesh);
    FormFactorStats stats;
    stats.patches = n;
    stats.pairs = n < 2 ? 0 : uint64_t(n) * (n - 1) / 2;

    // Counting pass: candidates of each row below and above the diagonal. facingAway is
    // symmetric (the same two tests either way), so each row is counted independently.
    std::vector<uint32_t> lowerCount(n, 0);
    std::vector<uint32_t> upperCount(n, 0);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 16),
                      [&](const tbb::blocked_range<uint32_t>& rows) {
                          for (uint32_t i = rows.begin(); i != rows.end(); ++i) {
                              uint32_t lower = 0;
                              uint32_t upper = 0;
                              for (uint32_t j = 0; j < n; ++j) {
                                  if (j == i || shared::facingAway(geometry[i], geometry[j])) {
                                      continue;
                                  }
                                  (j < i ? lower : upper) += 1;
                              }
                              lowerCount[i] = lower;
                              upperCount[i] = upper;
                          }
                      });
    uint64_t candidatePairs = 0;
    for (uint32_t i = 0; i < n; ++i)
        candidatePairs += upperCount[i];
    stats.facingAway = stats.pairs - candidatePairs;
    stats.slots = 2 * candidatePairs;
    stats.countSeconds = secondsSince(start);
    const std::size_t capacity = std::max<std::size_t>(
        1, std::min<uint64_t>(batchPairs, std::max<uint64_t>(1, candidatePairs)));
    stats.workBytes = pairBatchWorkBytes(n, candidatePairs, capacity);
    if (settings.maxMemoryBytes > 0 && stats.workBytes > settings.maxMemoryBytes) {
        return Error{concat("the view-factor matrix needs ",
                            formatBytes(static_cast<double>(stats.workBytes)), " for ",
                            formatCount(candidatePairs), " facing pairs of ", formatCount(n),
                            " patches, more than --max-memory ",
                            formatBytes(static_cast<double>(settings.maxMemoryBytes)),
                            "; use fewer patches (a larger --subdivide) or raise --max-memory")};
    }

    SparseMatrix matrix;
    matrix.size = n;
    matrix.rowOffsets.assign(std::size_t(n) + 1, 0);
    for (uint32_t i = 0; i < n; ++i)
        matrix.rowOffsets[i + 1] = matrix.rowOffsets[i] + lowerCount[i] + upperCount[i];
    matrix.columns.resize(stats.slots);
    matrix.values.resize(stats.slots);
    // Row i holds its columns j < i first, then j > i. Pairs arrive in row order (i, then j
    // ascending), so both parts of every row fill in ascending column order through a cursor.
    std::vector<uint64_t> lowerCursor(n);
    std::vector<uint64_t> upperCursor(n);
    for (uint32_t i = 0; i < n; ++i) {
        lowerCursor[i] = matrix.rowOffsets[i];
        upperCursor[i] = matrix.rowOffsets[i] + lowerCount[i];
    }
    lowerCount = {};
    upperCount = {};

    const auto pairStart = Clock::now();
    {
        Progress progress("view factors", candidatePairs, "pairs",
                          settings.progress && progressEnabledByDefault(), settings.onProgress);
        std::vector<PairIndex> batch;
        batch.reserve(capacity);
        std::vector<PairFactors> results;
        Cursor cursor;
        while (true) {
            if (isCancelled(settings.cancel)) return Error{kInterruptedMessage};
            cursor = nextBatch(geometry, cursor, capacity, batch);
            if (batch.empty()) break;
            results.assign(batch.size(), PairFactors{0.0f, 0.0f});
            Expected<void> done = evaluate(batch, results);
            if (!done) return withContext(done.error(), concat("backend '", backendName, "'"));
            for (std::size_t k = 0; k < batch.size(); ++k) {
                const uint32_t i = batch[k].i;
                const uint32_t j = batch[k].j;
                const float fij = results[k].fij;
                if (!(std::isfinite(fij) && fij >= 0.0f)) {
                    return Error{concat("backend '", backendName, "' returned F_", i, ",", j, " = ",
                                        fij, " (not a finite factor >= 0)")};
                }
                // F_ji from reciprocity in double, exactly as the cpu driver stores it, so the
                // matrices agree bit for bit wherever the kernels' F_ij do.
                const uint64_t slot = upperCursor[i]++;
                const uint64_t mirrorSlot = lowerCursor[j]++;
                matrix.columns[slot] = j;
                matrix.values[slot] = fij;
                matrix.columns[mirrorSlot] = i;
                matrix.values[mirrorSlot] =
                    static_cast<float>(double(fij) * (mesh.areas[i] / mesh.areas[j]));
                stats.zeroFactor += fij == 0.0f ? 1 : 0;
            }
            progress.advance(batch.size());
        }
    }
    stats.pairSeconds = secondsSince(pairStart);
    if (settings.raysPerPair > 0) {
        // The kernel traces every candidate pair with a non-zero unoccluded factor; which ones
        // had a zero factor it does not report, so these count all candidates (an upper bound).
        stats.tracedPairs = candidatePairs;
        stats.raysCast = candidatePairs * uint64_t(settings.raysPerPair);
    }

    const auto compactStart = Clock::now();
    dropZeros(matrix);
    stats.compactSeconds = secondsSince(compactStart);
    stats.nonzeros = matrix.nonzeroCount();
    stats.totalSeconds = secondsSince(start);
    return FormFactorResult{std::move(matrix), stats};
}

}  // namespace

std::vector<PatchGeometry> kernelPatches(const PatchMesh& mesh) {
    return detail::kernelGeometry(mesh);
}

float shadowClearance(const PatchMesh& mesh) {
    Bounds3d bounds;
    for (const Vec3d& p : mesh.positions)
        bounds.extend(p);
    return static_cast<float>(kEndClearanceRelative * std::max(1e-300, bounds.diagonal()));
}

Expected<FormFactorResult> buildFromPairBatches(const PatchMesh& mesh,
                                                const FormFactorSettings& settings,
                                                const char* backendName, std::size_t batchPairs,
                                                const PairEvaluator& evaluate) {
    if (settings.method == FormFactorMethod::Stochastic) {
        return Error{concat("backend '", backendName,
                            "' has no stochastic method (its rays are per patch, not per pair); "
                            "use --method hybrid, riemann or nusselt, or --backend cpu")};
    }
    if (settings.quadratureLevel < 0 || settings.quadratureLevel > DAISY_MAX_QUADRATURE_LEVEL) {
        return Error{concat("--quadrature ", settings.quadratureLevel, " is outside 0..",
                            DAISY_MAX_QUADRATURE_LEVEL)};
    }
    if (settings.raysPerPair < 0) return Error{"ray counts must be positive"};
    if (mesh.patchCount() > UINT32_MAX - 1) return Error{"too many patches for 32-bit indices"};
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    return arena.execute(
        [&]() { return build(mesh, settings, backendName, batchPairs, evaluate); });
}

}  // namespace daisy
