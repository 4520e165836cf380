#pragma once
// Entry-by-entry comparison of two view-factor matrices over the union of their sparsity
// patterns (`daisy validate`, backend tests, the stress suite). Absent entries count as 0.
#include <cstdint>
#include <vector>

#include "radiosity/sparse_matrix.h"

namespace daisy {

struct MatrixCompareSettings {
    // An entry agrees when |a - b| <= relativeTolerance * max(|a|, |b|) + absoluteTolerance.
    double relativeTolerance = 0;
    double absoluteTolerance = 0;
    int worstKept = 0;  // entries kept in MatrixComparison::worst
};

struct EntryDifference {
    uint32_t row = 0;
    uint32_t column = 0;
    float a = 0;  // the first matrix's value (0 when not stored)
    float b = 0;  // the second matrix's
    double absolute = 0;  // |a - b|
    double relative = 0;  // absolute / max(|a|, |b|); 0 when both are 0
    double excess = 0;  // absolute / the entry's bound (absolute when the bound is 0): > 1 is over
};

struct MatrixComparison {
    uint64_t unionEntries = 0;  // entries stored in either matrix
    uint64_t onlyInA = 0;  // stored in a only
    uint64_t onlyInB = 0;
    uint64_t overTolerance = 0;
    EntryDifference maxAbsolute;  // the first (row-major) entry of largest |a - b|
    EntryDifference maxRelative;  // the first entry of largest relative difference
    // The differing entries (|a - b| > 0) of largest excess, largest first, at most worstKept.
    std::vector<EntryDifference> worst;
};

// Walks both matrices row by row in column order. Precondition: a.size == b.size (DAISY_CHECK);
// both structurally valid (validateStructure).
MatrixComparison compareMatrices(const SparseMatrix& a, const SparseMatrix& b,
                                 const MatrixCompareSettings& settings);

}  // namespace daisy
