// Energy bookkeeping against conservation: in steady state everything emitted is absorbed or
// escapes through openings (DESIGN.md section 6; energy.h).
#include "radiosity/energy.h"

#include <gtest/gtest.h>

#include "radiosity/solver.h"
#include "radiosity/solver_test_util.h"

namespace daisy {
namespace {

using solvertest::diagonalOperator;
using solvertest::furnaceMatrix;
using solvertest::makeSystem;
using solvertest::matrixOperator;
using solvertest::randomSystem;

SolverResult solveTight(const SparseMatrix& f, const RadiositySystem& system) {
    SolverSettings settings;
    settings.tolerance = 1e-13;
    settings.maxIterations = 100000;
    auto result = solveRadiosity(f, system, settings);
    EXPECT_TRUE(result.ok());
    return std::move(*result);
}

// Closed furnace, rho = 0.9: nothing escapes, so absorbed = emitted; B = E / (1 - rho) and
// absorbed = (1 - rho) x incident = (1 - rho) B = E per patch.
TEST(Energy, ClosedFurnaceAbsorbsAllItEmits) {
    const SparseMatrix f = furnaceMatrix(9);
    RadiositySystem system = makeSystem(9, 2, {diagonalOperator({0.9, 0.9})});
    system.emission[0] = 3;
    system.emission[5] = 1;
    const SolverResult result = solveTight(f, system);
    const EnergyBalance balance =
        computeEnergyBalance(system, rowSums(f), result.radiosity, result.gathered);
    EXPECT_DOUBLE_EQ(balance.emitted, 4);
    EXPECT_NEAR(balance.escaped, 0, 1e-12);
    EXPECT_NEAR(balance.absorbed, 4, 1e-9);
    EXPECT_EQ(balance.converted, 0);
    EXPECT_NEAR(balance.imbalance(), 0, 1e-10);
}

// An open enclosure with reciprocal F, fluorescent, plain and black patches: the balance
// closes to the solve's residual (1e-13) and float rounding of F's reciprocity (~1e-7).
TEST(Energy, OpenFluorescentSceneBalances) {
    const auto [f, system] = randomSystem(60, 6, 0.8, 0.4, 21);
    const SolverResult result = solveTight(f, system);
    const EnergyBalance balance =
        computeEnergyBalance(system, rowSums(f), result.radiosity, result.gathered);
    EXPECT_GT(balance.escaped, 0.05 * balance.emitted);
    EXPECT_GT(balance.converted, 0);
    EXPECT_NEAR(balance.imbalance(), 0, 1e-6);
    double perSample = 0;
    for (std::size_t k = 0; k < 6; ++k)
        perSample += balance.emittedPerSample[k] - balance.absorbedPerSample[k] -
            balance.escapedPerSample[k];
    EXPECT_NEAR(perSample / balance.emitted, 0, 1e-6);
}

// Fluorescent furnace: G_i = B_i (row sums 1, uniform B), so the converted power is
// sum_i A_i sum_o w_o sum_{k<o} M[o][k] B[k], here 9 x (0.3 B0 + 0.1 B0 + 0.2 B1) with
// B = (I - M)^-1 E (solver_test.cpp's FluorescentFurnace oracle).
TEST(Energy, FluorescentFurnaceConvertedPower) {
    const std::vector<double> m3 = {0.5, 0, 0, 0.3, 0.4, 0, 0.1, 0.2, 0.6};
    RadiositySystem system = makeSystem(9, 3, {matrixOperator(3, m3)});
    for (uint32_t i = 0; i < 9; ++i) {
        system.emission[i * 3 + 0] = 2;
        system.emission[i * 3 + 1] = 1;
        system.emission[i * 3 + 2] = 0.5;
    }
    const SparseMatrix f = furnaceMatrix(9);
    const SolverResult result = solveTight(f, system);
    const EnergyBalance balance =
        computeEnergyBalance(system, rowSums(f), result.radiosity, result.gathered);
    const double b0 = 4, b1 = (1 + 0.3 * b0) / 0.6;
    EXPECT_NEAR(balance.converted, 9 * (0.4 * b0 + 0.2 * b1), 1e-8);
    EXPECT_NEAR(balance.imbalance(), 0, 1e-10);
}

}  // namespace
}  // namespace daisy
