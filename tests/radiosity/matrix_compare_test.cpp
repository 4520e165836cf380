// compareMatrices on small matrices whose every difference is worked out by hand: values are
// binary fractions, so each |a - b| and bound is exact and the expected counts are exact.
#include "radiosity/matrix_compare.h"

#include <gtest/gtest.h>

#include <vector>

namespace daisy {
namespace {

// A CSR matrix from its rows, each a list of (column, value) in ascending column order.
SparseMatrix csr(const std::vector<std::vector<std::pair<uint32_t, float>>>& rows) {
    SparseMatrix m = SparseMatrix::zeros(uint32_t(rows.size()));
    for (std::size_t i = 0; i < rows.size(); ++i) {
        for (const auto& [column, value] : rows[i]) {
            m.columns.push_back(column);
            m.values.push_back(value);
        }
        m.rowOffsets[i + 1] = m.columns.size();
    }
    EXPECT_EQ(validateStructure(m), "");
    return m;
}

// Entries: (0, 0) equal; (0, 1) only in a (0.25 vs 0); (1, 0) only in b (0 vs 0.125); (1, 1)
// both (1 vs 0.75).
SparseMatrix matrixA() {
    return csr({{{0, 0.5f}, {1, 0.25f}}, {{1, 1.0f}}});
}
SparseMatrix matrixB() {
    return csr({{{0, 0.5f}}, {{0, 0.125f}, {1, 0.75f}}});
}

TEST(MatrixCompare, CountsTheUnionOfThePatterns) {
    const MatrixComparison c = compareMatrices(matrixA(), matrixB(), {});
    EXPECT_EQ(c.unionEntries, 4u);
    EXPECT_EQ(c.onlyInA, 1u);
    EXPECT_EQ(c.onlyInB, 1u);
    EXPECT_EQ(c.overTolerance, 3u);  // tolerances 0: every differing entry
    EXPECT_TRUE(c.worst.empty());  // worstKept 0
}

TEST(MatrixCompare, MaxDifferencesAndTheirPlaces) {
    const MatrixComparison c = compareMatrices(matrixA(), matrixB(), {});
    // |a - b| = 0.25 at (0, 1) and (1, 1): the first in row-major order wins.
    EXPECT_EQ(c.maxAbsolute.absolute, 0.25);
    EXPECT_EQ(c.maxAbsolute.row, 0u);
    EXPECT_EQ(c.maxAbsolute.column, 1u);
    EXPECT_EQ(c.maxAbsolute.a, 0.25f);
    EXPECT_EQ(c.maxAbsolute.b, 0.0f);
    // Relative 1 at (0, 1) and (1, 0) (an entry against 0), 0.25 at (1, 1).
    EXPECT_EQ(c.maxRelative.relative, 1);
    EXPECT_EQ(c.maxRelative.row, 0u);
    EXPECT_EQ(c.maxRelative.column, 1u);
}

TEST(MatrixCompare, ToleranceIsRelativePlusAbsoluteAndInclusive) {
    // rtol 0.25: (1, 1) has bound 0.25 max(1, 0.75) = 0.25 = |a - b|: within (<=).
    EXPECT_EQ(compareMatrices(matrixA(), matrixB(), {0.25, 0, 0}).overTolerance, 2u);
    // atol 0.125 alone: (1, 0) is exactly on the bound; (0, 1) and (1, 1) are over.
    EXPECT_EQ(compareMatrices(matrixA(), matrixB(), {0, 0.125, 0}).overTolerance, 2u);
    // rtol 0.5 + atol 0.125: (0, 1) bound 0.25, (1, 0) 0.1875, (1, 1) 0.625: none over.
    EXPECT_EQ(compareMatrices(matrixA(), matrixB(), {0.5, 0.125, 0}).overTolerance, 0u);
}

TEST(MatrixCompare, WorstEntriesByExcessLargestFirst) {
    // rtol 0.5, atol 0.0625: bounds (0, 1) 0.1875, (1, 0) 0.125, (1, 1) 0.5625; excess
    // 0.25 / 0.1875 = 4/3, 0.125 / 0.125 = 1, 0.25 / 0.5625 = 4/9.
    const MatrixComparison all = compareMatrices(matrixA(), matrixB(), {0.5, 0.0625, 10});
    ASSERT_EQ(all.worst.size(), 3u);  // the equal entry (0, 0) is not listed
    EXPECT_EQ(all.worst[0].row, 0u);
    EXPECT_EQ(all.worst[0].column, 1u);
    EXPECT_DOUBLE_EQ(all.worst[0].excess, 4.0 / 3);
    EXPECT_EQ(all.worst[1].row, 1u);
    EXPECT_EQ(all.worst[1].column, 0u);
    EXPECT_DOUBLE_EQ(all.worst[1].excess, 1);
    EXPECT_EQ(all.worst[2].row, 1u);
    EXPECT_EQ(all.worst[2].column, 1u);
    EXPECT_DOUBLE_EQ(all.worst[2].excess, 4.0 / 9);
    EXPECT_EQ(all.overTolerance, 1u);
    const MatrixComparison two = compareMatrices(matrixA(), matrixB(), {0.5, 0.0625, 2});
    ASSERT_EQ(two.worst.size(), 2u);
    EXPECT_EQ(two.worst[0].column, 1u);
    EXPECT_EQ(two.worst[1].column, 0u);
    // Both tolerances 0: ranked by |a - b|.
    const MatrixComparison plain = compareMatrices(matrixA(), matrixB(), {0, 0, 1});
    ASSERT_EQ(plain.worst.size(), 1u);
    EXPECT_EQ(plain.worst[0].excess, 0.25);
}

TEST(MatrixCompare, IdenticalAndEmptyMatrices) {
    const MatrixComparison same = compareMatrices(matrixA(), matrixA(), {0, 0, 5});
    EXPECT_EQ(same.unionEntries, 3u);
    EXPECT_EQ(same.onlyInA + same.onlyInB + same.overTolerance, 0u);
    EXPECT_EQ(same.maxAbsolute.absolute, 0);
    EXPECT_TRUE(same.worst.empty());
    const MatrixComparison empty =
        compareMatrices(SparseMatrix::zeros(3), SparseMatrix::zeros(3), {0, 0, 5});
    EXPECT_EQ(empty.unionEntries, 0u);
    EXPECT_EQ(empty.overTolerance, 0u);
}

}  // namespace
}  // namespace daisy
