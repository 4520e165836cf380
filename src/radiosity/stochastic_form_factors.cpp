// The stochastic method: closest-hit rays per patch, then the reciprocal average of the two
// estimates of every pair (docs/formfactors.md).
#include "radiosity/stochastic_form_factors.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "radiosity/kernel_inputs.h"
#include "shared/config.h"
#include "shared/rng.h"
#include "shared/sampling.h"

namespace daisy::detail {

using shared::PatchGeometry;
using shared::vec3;

// stochastic: N cosine-weighted rays leave each patch i from stratified points
// (shared::stochasticRay); the raw estimate R_ij = hits_j / N includes visibility but is not
// reciprocal. Each unordered pair gets the area-weighted mean of its two estimates,
// A_i F_ij = A_j F_ji = (A_i R_ij + A_j R_ji) / 2, which is unbiased for both entries and
// reciprocal by construction; row sums are then 1 in expectation (each R row sums to exactly 1
// in a closed enclosure), not exactly.
Expected<FormFactorResult> computeStochastic(const PatchMesh& mesh,
                                             const FormFactorSettings& settings,
                                             const RayCaster& rays) {
    const auto start = Clock::now();
    const auto n = static_cast<uint32_t>(mesh.patchCount());
    const int rayCount = settings.stochasticRays;
    FormFactorStats stats;
    stats.patches = n;
    stats.pairs = n < 2 ? 0 : uint64_t(n) * (n - 1) / 2;
    // R, its transpose and F each hold at most min(N, n - 1) entries a row.
    const uint64_t rowBound = std::min<uint64_t>(uint64_t(rayCount), n > 0 ? n - 1 : 0);
    stats.workBytes = 3 * sparseMatrixBytes(n, uint64_t(n) * rowBound);
    if (settings.maxMemoryBytes > 0 && stats.workBytes > settings.maxMemoryBytes) {
        return Error{concat("the stochastic view-factor matrix may need ",
                            formatBytes(static_cast<double>(stats.workBytes)), " for ",
                            formatCount(n), " patches and ", rayCount,
                            " rays each, more than --max-memory ",
                            formatBytes(static_cast<double>(settings.maxMemoryBytes)))};
    }
    const std::vector<PatchGeometry> geometry = kernelPatches(mesh);
    const uint32_t seed = kernelSeed(settings.seed);

    // Raw estimate, built in row chunks (each chunk's rows in order), then concatenated.
    constexpr uint32_t kRowsPerChunk = 32;
    const uint32_t chunkCount = (n + kRowsPerChunk - 1) / kRowsPerChunk;
    struct Chunk {
        std::vector<uint32_t> rowLength, columns;
        std::vector<float> values;
    };
    std::vector<Chunk> chunks(chunkCount);
    {
        Progress progress("stochastic rays", uint64_t(n) * uint64_t(rayCount), "rays",
                          settings.progress && progressEnabledByDefault(), settings.onProgress);
        tbb::parallel_for(uint32_t(0), chunkCount, [&](uint32_t c) {
            if (isCancelled(settings.cancel)) return;
            Chunk& chunk = chunks[c];
            std::vector<Ray> batch(static_cast<std::size_t>(rayCount));
            std::vector<uint32_t> hits(batch.size());
            for (uint32_t i = c * kRowsPerChunk; i < std::min(n, (c + 1) * kRowsPerChunk); ++i) {
                const uint32_t patchSeedValue = shared::patchSeed(i, seed);
                for (int k = 0; k < rayCount; ++k) {
                    vec3 origin, direction;
                    shared::stochasticRay(patchSeedValue, k, rayCount, geometry[i], origin,
                                          direction);
                    batch[k] = Ray{{origin.x, origin.y, origin.z},
                                   {direction.x, direction.y, direction.z}};
                }
                rays.closestHits(batch, hits);
                std::sort(hits.begin(), hits.end());
                uint32_t length = 0;
                for (std::size_t k = 0; k < hits.size();) {
                    std::size_t end = k;
                    while (end < hits.size() && hits[end] == hits[k])
                        ++end;
                    if (hits[k] != kNoPatch && hits[k] != i) {
                        chunk.columns.push_back(hits[k]);
                        chunk.values.push_back(
                            static_cast<float>(double(end - k) / double(rayCount)));
                        ++length;
                    }
                    k = end;
                }
                chunk.rowLength.push_back(length);
                progress.advance(uint64_t(rayCount));
            }
        });
    }
    if (isCancelled(settings.cancel)) return Error{kInterruptedMessage};
    SparseMatrix raw = SparseMatrix::zeros(n);
    for (const Chunk& chunk : chunks) {
        raw.columns.insert(raw.columns.end(), chunk.columns.begin(), chunk.columns.end());
        raw.values.insert(raw.values.end(), chunk.values.begin(), chunk.values.end());
    }
    for (uint32_t c = 0, i = 0; c < chunkCount; ++c) {
        for (uint32_t length : chunks[c].rowLength) {
            raw.rowOffsets[i + 1] = raw.rowOffsets[i] + length;
            ++i;
        }
    }
    chunks = {};
    const SparseMatrix rawT = transpose(raw);
    stats.pairSeconds = secondsSince(start);

    // Union of the patterns of R and R^T, row by row: count, then fill.
    const auto mergeStart = Clock::now();
    SparseMatrix f = SparseMatrix::zeros(n);
    std::vector<uint64_t> length(n);
    tbb::parallel_for(uint32_t(0), n, [&](uint32_t i) {
        const auto a = raw.rowColumns(i);
        const auto b = rawT.rowColumns(i);
        std::size_t x = 0, y = 0, count = 0;
        while (x < a.size() || y < b.size()) {
            const uint32_t ca = x < a.size() ? a[x] : UINT32_MAX;
            const uint32_t cb = y < b.size() ? b[y] : UINT32_MAX;
            x += ca <= cb ? 1 : 0;
            y += cb <= ca ? 1 : 0;
            ++count;
        }
        length[i] = count;
    });
    for (uint32_t i = 0; i < n; ++i)
        f.rowOffsets[i + 1] = f.rowOffsets[i] + length[i];
    f.columns.resize(f.rowOffsets[n]);
    f.values.resize(f.rowOffsets[n]);
    tbb::parallel_for(uint32_t(0), n, [&](uint32_t i) {
        const auto a = raw.rowColumns(i);
        const auto av = raw.rowValues(i);
        const auto b = rawT.rowColumns(i);
        const auto bv = rawT.rowValues(i);
        std::size_t x = 0, y = 0;
        uint64_t out = f.rowOffsets[i];
        while (x < a.size() || y < b.size()) {
            const uint32_t ca = x < a.size() ? a[x] : UINT32_MAX;
            const uint32_t cb = y < b.size() ? b[y] : UINT32_MAX;
            const uint32_t j = std::min(ca, cb);
            const double rij = ca == j ? double(av[x++]) : 0.0;
            const double rji = cb == j ? double(bv[y++]) : 0.0;  // R^T row i holds R_ji
            f.columns[out] = j;
            f.values[out++] = static_cast<float>(0.5 * (mesh.areas[i] * rij + mesh.areas[j] * rji) /
                                                 mesh.areas[i]);
        }
    });
    stats.compactSeconds = secondsSince(mergeStart);
    stats.raysCast = uint64_t(n) * uint64_t(rayCount);
    stats.slots = f.nonzeroCount();
    stats.nonzeros = f.nonzeroCount();
    stats.totalSeconds = secondsSince(start);
    return FormFactorResult{std::move(f), stats};
}

}  // namespace daisy::detail
