#include "radiosity/sparse_matrix.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#include "core/strings.h"

namespace daisy {

SparseMatrix SparseMatrix::zeros(uint32_t n) {
    SparseMatrix matrix;
    matrix.size = n;
    matrix.rowOffsets.assign(std::size_t(n) + 1, 0);
    return matrix;
}

float SparseMatrix::at(uint32_t row, uint32_t column) const {
    const auto rowCols = rowColumns(row);
    const auto it = std::lower_bound(rowCols.begin(), rowCols.end(), column);
    if (it == rowCols.end() || *it != column) return 0.0f;
    return values[rowOffsets[row] + static_cast<uint64_t>(it - rowCols.begin())];
}

uint64_t SparseMatrix::bytes() const {
    return sparseMatrixBytes(size, nonzeroCount());
}

uint64_t sparseMatrixBytes(uint64_t rows, uint64_t nonzeros) {
    return 8 * (rows + 1) + (sizeof(uint32_t) + sizeof(float)) * nonzeros;
}

std::vector<double> rowSums(const SparseMatrix& matrix) {
    std::vector<double> sums(matrix.size, 0.0);
    tbb::parallel_for(uint32_t(0), matrix.size, [&](uint32_t i) {
        for (float value : matrix.rowValues(i))
            sums[i] += value;
    });
    return sums;
}

RowSumCap capRowSums(SparseMatrix& matrix) {
    const std::vector<double> sums = rowSums(matrix);
    RowSumCap cap;
    std::vector<double> scale(matrix.size, 1.0);
    for (uint32_t i = 0; i < matrix.size; ++i) {
        cap.largestRowSum = std::max(cap.largestRowSum, sums[i]);
        if (sums[i] > 1.0) {
            scale[i] = 1.0 / sums[i];
            ++cap.rowsCapped;
        }
    }
    if (cap.rowsCapped == 0) return cap;
    tbb::parallel_for(uint32_t(0), matrix.size, [&](uint32_t i) {
        const uint64_t end = matrix.rowOffsets[i + 1];
        for (uint64_t k = matrix.rowOffsets[i]; k < end; ++k) {
            const double s = scale[i] * scale[matrix.columns[k]];
            if (s != 1.0) matrix.values[k] = static_cast<float>(matrix.values[k] * s);
        }
    });
    return cap;
}

SparseMatrix transpose(const SparseMatrix& matrix) {
    SparseMatrix result = SparseMatrix::zeros(matrix.size);
    for (uint32_t column : matrix.columns)
        ++result.rowOffsets[column + 1];
    for (uint32_t j = 0; j < matrix.size; ++j)
        result.rowOffsets[j + 1] += result.rowOffsets[j];
    result.columns.resize(matrix.nonzeroCount());
    result.values.resize(matrix.nonzeroCount());
    std::vector<uint64_t> next(result.rowOffsets.begin(), result.rowOffsets.end() - 1);
    for (uint32_t i = 0; i < matrix.size; ++i) {
        for (uint64_t k = matrix.rowOffsets[i]; k < matrix.rowOffsets[i + 1]; ++k) {
            const uint64_t target = next[matrix.columns[k]]++;
            result.columns[target] = i;
            result.values[target] = matrix.values[k];
        }
    }
    return result;
}

namespace {

// Gives the whole pages beyond a vector's size back to the operating system without moving the
// data (Linux: madvise MADV_DONTNEED; the pages read as zeros if touched again). shrink_to_fit
// would copy, briefly holding both arrays: that copy was the build's peak memory and ~0.1 s.
template <typename T, typename Allocator>
void releaseUnusedCapacity(std::vector<T, Allocator>& v) {
#if defined(__linux__)
    const auto page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
    const auto begin = reinterpret_cast<uintptr_t>(v.data() + v.size());
    const auto end = reinterpret_cast<uintptr_t>(v.data() + v.capacity());
    const uintptr_t first = (begin + page - 1) / page * page;
    const uintptr_t last = end / page * page;
    if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_DONTNEED);
#else
    v.shrink_to_fit();
#endif
}

}  // namespace

void dropZeros(SparseMatrix& matrix) {
    // Two phases, so the rows can be compacted in parallel in place: each chunk of rows first
    // packs its kept entries at the start of its own range, then the chunks move down in order
    // (each destination lies at or before its source, so memmove is safe).
    const uint32_t n = matrix.size;
    const uint32_t chunkCount = std::max(1u, std::min(n, 256u));
    std::vector<uint32_t> chunkBegin(chunkCount + 1);
    for (uint32_t c = 0; c <= chunkCount; ++c)
        chunkBegin[c] = static_cast<uint32_t>(uint64_t(n) * c / chunkCount);
    std::vector<uint64_t> kept(std::size_t(n) + 1, 0);  // kept[i + 1]: row i's kept entries
    tbb::parallel_for(uint32_t(0), chunkCount, [&](uint32_t c) {
        uint64_t out = matrix.rowOffsets[chunkBegin[c]];
        for (uint32_t i = chunkBegin[c]; i < chunkBegin[c + 1]; ++i) {
            const uint64_t before = out;
            for (uint64_t k = matrix.rowOffsets[i]; k < matrix.rowOffsets[i + 1]; ++k) {
                if (matrix.values[k] != 0.0f) {
                    matrix.columns[out] = matrix.columns[k];
                    matrix.values[out] = matrix.values[k];
                    ++out;
                }
            }
            kept[i + 1] = out - before;
        }
    });
    uint64_t out = 0;
    for (uint32_t c = 0; c < chunkCount; ++c) {
        const uint64_t source = matrix.rowOffsets[chunkBegin[c]];
        uint64_t length = 0;
        for (uint32_t i = chunkBegin[c]; i < chunkBegin[c + 1]; ++i)
            length += kept[i + 1];
        if (length == 0) continue;  // empty chunk: data() may be null (memmove's UB)
        std::memmove(matrix.columns.data() + out, matrix.columns.data() + source,
                     length * sizeof(uint32_t));
        std::memmove(matrix.values.data() + out, matrix.values.data() + source,
                     length * sizeof(float));
        out += length;
    }
    for (uint32_t i = 0; i < n; ++i)
        matrix.rowOffsets[i + 1] = matrix.rowOffsets[i] + kept[i + 1];
    matrix.columns.resize(out);
    matrix.values.resize(out);
    releaseUnusedCapacity(matrix.columns);
    releaseUnusedCapacity(matrix.values);
}

std::string validateStructure(const SparseMatrix& matrix) {
    if (matrix.rowOffsets.size() != std::size_t(matrix.size) + 1) {
        return concat("rowOffsets has ", matrix.rowOffsets.size(), " entries, expected ",
                      uint64_t(matrix.size) + 1);
    }
    if (matrix.columns.size() != matrix.values.size()) return "columns and values differ in size";
    if (matrix.rowOffsets.front() != 0 || matrix.rowOffsets.back() != matrix.columns.size()) {
        return "rowOffsets do not span the entries";
    }
    for (uint32_t i = 0; i < matrix.size; ++i) {
        if (matrix.rowOffsets[i + 1] < matrix.rowOffsets[i]) {
            return concat("rowOffsets decrease at row ", i);
        }
        const auto cols = matrix.rowColumns(i);
        const auto vals = matrix.rowValues(i);
        for (std::size_t k = 0; k < cols.size(); ++k) {
            if (cols[k] >= matrix.size) return concat("row ", i, ": column ", cols[k], " >= size");
            if (k > 0 && cols[k] <= cols[k - 1]) {
                return concat("row ", i, ": columns not strictly ascending at ", cols[k]);
            }
            if (!std::isfinite(vals[k])) return concat("row ", i, ": non-finite value");
        }
    }
    return {};
}

}  // namespace daisy
