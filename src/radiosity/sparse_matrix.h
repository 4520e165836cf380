#pragma once
// The view-factor matrix F in compressed sparse row form (DESIGN.md section 3): uint64 row
// offsets, uint32 column indices, float values. Row i holds the non-zero F_ij in ascending
// column order; absent entries are zero. F is square (patches x patches).
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/memory.h"

namespace daisy {

struct SparseMatrix {
    uint32_t size = 0;  // rows = columns = patch count
    std::vector<uint64_t> rowOffsets;  // size + 1; row i is [rowOffsets[i], rowOffsets[i + 1])
    // Per stored entry: columns ascending within a row, and values. resize() leaves new entries
    // unset (UninitializedVector): whoever grows them writes every one.
    UninitializedVector<uint32_t> columns;
    UninitializedVector<float> values;

    // An all-zero n x n matrix (offsets only).
    static SparseMatrix zeros(uint32_t n);

    uint64_t nonzeroCount() const { return columns.size(); }
    uint64_t rowLength(uint32_t row) const { return rowOffsets[row + 1] - rowOffsets[row]; }
    std::span<const uint32_t> rowColumns(uint32_t row) const {
        return {columns.data() + rowOffsets[row], rowLength(row)};
    }
    std::span<const float> rowValues(uint32_t row) const {
        return {values.data() + rowOffsets[row], rowLength(row)};
    }
    // Entry (row, column) by binary search; 0 when not stored. O(log row length).
    float at(uint32_t row, uint32_t column) const;
    // Bytes held by the three arrays: 8 (n + 1) + 8 nnz.
    uint64_t bytes() const;
};

// CSR bytes for n rows and nnz stored entries: 8 (n + 1) + (4 + 4) nnz.
uint64_t sparseMatrixBytes(uint64_t rows, uint64_t nonzeros);

// Sum of each row, accumulated in double (rows in parallel, each in order: deterministic).
std::vector<double> rowSums(const SparseMatrix& matrix);

// What capRowSums did: rows scaled, and the largest row sum before.
struct RowSumCap {
    uint64_t rowsCapped = 0;
    double largestRowSum = 0;
};

// Conservation of energy for a matrix of view factors: no row of F may sum above 1,
// but sampled visibility can push a row over (K shadow segments estimate V_ij with an error of
// up to 1/K). Scales every entry F_ij by s_i s_j with s_i = min(1, 1 / rowsum_i): row i then
// sums to at most s_i rowsum_i = 1 (s_j <= 1), rows at or under 1 whose neighbours are too are
// untouched, and since F_ij and F_ji get the same factor, reciprocity (A_i F_ij = A_j F_ji)
// holds as before. Deterministic, parallel over rows.
RowSumCap capRowSums(SparseMatrix& matrix);

// The transpose, rows in ascending column order (a counting sort: O(n + nnz), deterministic).
SparseMatrix transpose(const SparseMatrix& matrix);

// Removes stored entries equal to zero, in place (rows compacted in parallel), keeping order;
// the memory past the new end is returned to the system without copying the arrays.
void dropZeros(SparseMatrix& matrix);

// Checks the structure: offsets monotone and consistent, columns in range and strictly
// ascending per row, values finite. Returns an empty string or what is wrong (for tests and
// DAISY_CHECKs).
std::string validateStructure(const SparseMatrix& matrix);

}  // namespace daisy
