// The all-pairs transport (radiosity/matrix_transport.h) on small matrices whose products are
// known exactly: gathers, the emitters' gather, rows, row sums, solves, export and comparison.
#include "radiosity/matrix_transport.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "radiosity/matrix_market.h"
#include "test_util.h"

namespace daisy {
namespace {

// 3 patches: F_01 = 1/4, F_02 = 1/2, F_10 = 1/8, F_21 = 3/4 (exact in float).
SparseMatrix smallMatrix() {
    SparseMatrix f = SparseMatrix::zeros(3);
    f.columns = {1, 2, 0, 1};
    f.values = {0.25f, 0.5f, 0.125f, 0.75f};
    f.rowOffsets = {0, 2, 3, 4};
    return f;
}

// One grey operator of reflectance rho on m = 1, unit bin, unit areas.
RadiositySystem greySystem(uint32_t n, double rho, std::vector<double> emission) {
    RadiositySystem system;
    system.patchCount = n;
    system.wavelengthCount = 1;
    system.wavelengthsNm = {550};
    system.binWidthsNm = {1};
    system.emission = std::move(emission);
    system.areas.assign(n, 1.0);
    system.patchOperator.assign(n, 0);
    MaterialOperator op;
    op.matrix.size = 1;
    op.matrix.values = {rho};
    finishOperator(op, system.binWidthsNm);
    system.operators = {op};
    return system;
}

TEST(MatrixTransport, GathersRowSumsAndRowsAreFsProducts) {
    const MatrixTransport transport(smallMatrix());
    EXPECT_STREQ(transport.kind(), "matrix");
    EXPECT_EQ(transport.patchCount(), 3u);
    EXPECT_EQ(transport.stats().entries, 4u);
    EXPECT_EQ(transport.checkStructure(), "");
    const std::span<const double> sums = transport.rowSums();
    EXPECT_EQ(std::vector<double>(sums.begin(), sums.end()),
              (std::vector<double>{0.75, 0.125, 0.75}));

    // Two wavelengths: B = [[1, 2], [4, 8], [16, 32]].
    const std::vector<double> b = {1, 2, 4, 8, 16, 32};
    std::vector<double> g(6, -1);
    transport.gather(b, 2, g);
    EXPECT_EQ(g, (std::vector<double>{9, 18, 0.125, 0.25, 3, 6}));

    // Only patch 2 emits, only patches 0 and 2 receive: row 1 is left as it was.
    std::vector<double> direct(6, -1);
    transport.gatherFrom(std::vector<uint8_t>{0, 0, 1}, std::vector<uint8_t>{1, 0, 1}, b, 2,
                         direct);
    EXPECT_EQ(direct, (std::vector<double>{8, 16, -1, -1, 0, 0}));

    std::vector<TransportEntry> row;
    transport.row(0, row);
    ASSERT_EQ(row.size(), 2u);
    EXPECT_EQ(row[0].patch, 1u);
    EXPECT_EQ(row[0].factor, 0.25f);
    EXPECT_EQ(row[1].patch, 2u);
    EXPECT_EQ(row[1].factor, 0.5f);
}

// B = E + rho F B on the 3 patches, solved exactly by hand: with E = (1, 0, 0) and rho = 1/2,
// B_1 = rho F_10 B_0, B_2 = rho F_21 B_1, B_0 = 1 + rho (F_01 B_1 + F_02 B_2). Every solver,
// Southwell through the transpose the transport keeps, lands on it.
TEST(MatrixTransport, EverySolverSolvesTheSmallSystemExactly) {
    const MatrixTransport transport(smallMatrix());
    const RadiositySystem system = greySystem(3, 0.5, {1, 0, 0});
    const double c1 = 0.5 * 0.125, c2 = 0.5 * 0.75 * c1;  // B_1 = c1 B_0, B_2 = c2 B_0
    const double b0 = 1 / (1 - 0.5 * (0.25 * c1 + 0.5 * c2));
    for (const SolverKind kind :
         {SolverKind::GaussSeidel, SolverKind::Jacobi, SolverKind::Southwell}) {
        SolverSettings settings;
        settings.kind = kind;
        settings.tolerance = 1e-12;
        auto solved = transport.solve(system, settings);
        ASSERT_TRUE(solved.ok()) << solved.error().message;
        EXPECT_TRUE(solved->converged) << solverKindName(kind);
        EXPECT_NEAR(solved->radiosity[0], b0, 1e-10) << solverKindName(kind);
        EXPECT_NEAR(solved->radiosity[1], c1 * b0, 1e-10) << solverKindName(kind);
        EXPECT_NEAR(solved->radiosity[2], c2 * b0, 1e-10) << solverKindName(kind);
    }
}

TEST(MatrixTransport, WritesMatrixMarketThatReadsBackAsTheSameFactors) {
    const MatrixTransport transport(smallMatrix());
    const std::string path = (test::testTempDir() / "F.mtx").string();
    ASSERT_TRUE(transport.writeMatrixMarket(path, {"a comment"}).ok());
    auto read = readMatrixMarket(path);
    ASSERT_TRUE(read.ok()) << read.error().message;
    auto compared = transport.compare(MatrixTransport(std::move(*read)), {});
    ASSERT_TRUE(compared.ok()) << compared.error().message;
    EXPECT_EQ(compared->unionEntries, 4u);
    EXPECT_EQ(compared->overTolerance, 0u);
    EXPECT_EQ(compared->maxAbsolute.absolute, 0.0);
}

TEST(MatrixTransport, ComparisonFindsTheDifferingEntryAndRefusesOtherSizes) {
    const MatrixTransport a(smallMatrix());
    const auto b = denseTransport(3, [](uint32_t i, uint32_t j) {
        const float f[3][3] = {{0, 0.25f, 0.5f}, {0.125f, 0, 0.5f}, {0, 0.75f, 0}};
        return f[i][j];
    });
    auto compared = a.compare(*b, {});
    ASSERT_TRUE(compared.ok());
    EXPECT_EQ(compared->onlyInB, 1u);
    EXPECT_EQ(compared->overTolerance, 1u);
    EXPECT_EQ(compared->maxAbsolute.row, 1u);
    EXPECT_EQ(compared->maxAbsolute.column, 2u);
    EXPECT_FALSE(a.compare(*denseTransport(2, [](uint32_t, uint32_t) { return 0.5f; }), {}).ok());
}

TEST(MatrixTransport, DenseTransportStoresOnlyTheNonZeros) {
    const auto furnace =
        denseTransport(65, [](uint32_t i, uint32_t j) { return i == j ? 0.0f : 1.0f / 64; });
    EXPECT_EQ(furnace->stats().entries, 65u * 64u);
    for (const double sum : furnace->rowSums())
        EXPECT_DOUBLE_EQ(sum, 1.0);
}

}  // namespace
}  // namespace daisy
