// The radiosity solvers against closed forms (the furnace), a dense direct solve, the Neumann
// series and each other (DESIGN.md section 6).
#include "radiosity/solver.h"

#include <gtest/gtest.h>

#include <cmath>

#include "backend/backend.h"
#include "geometry/patch_mesh.h"
#include "radiosity/solver_test_util.h"

namespace daisy {
namespace {

using solvertest::denseSolve;
using solvertest::diagonalOperator;
using solvertest::furnaceMatrix;
using solvertest::makeSystem;
using solvertest::matrixOperator;
using solvertest::randomSystem;

constexpr SolverKind kAllSolvers[] = {SolverKind::GaussSeidel, SolverKind::Jacobi,
                                      SolverKind::Southwell};

SolverResult solveOk(const SparseMatrix& f, const RadiositySystem& system, SolverKind kind,
                     double tolerance = 1e-12, int threads = 0) {
    SolverSettings settings;
    settings.kind = kind;
    settings.tolerance = tolerance;
    settings.maxIterations = 100000;
    settings.threads = threads;
    auto result = solveRadiosity(f, system, settings);
    EXPECT_TRUE(result.ok()) << (result.ok() ? "" : result.error().message);
    return result.ok() ? std::move(*result) : SolverResult{};
}

double maxRelativeDifference(std::span<const double> a, std::span<const double> b) {
    double worst = 0;
    for (std::size_t k = 0; k < a.size(); ++k)
        worst = std::max(worst, std::abs(a[k] - b[k]) / std::max(std::abs(b[k]), 1e-300));
    return worst;
}

// Furnace: a closed enclosure (row sums 1) with uniform reflectance rho and emission E has the
// uniform solution B = E + rho B, i.e. B = E / (1 - rho) (Cohen & Wallace 1993, section 2.7's
// infinite-reflection argument; the "white furnace" test of renderers).
TEST(Solver, FurnaceOnExactMatrixGivesEOverOneMinusRho) {
    const SparseMatrix f = furnaceMatrix(9);  // F_ij = 1/8: exact in float
    for (double rho : {0.5, 0.9, 0.99}) {
        RadiositySystem system = makeSystem(9, 3, {diagonalOperator({rho, rho, rho})});
        for (std::size_t k = 0; k < system.emission.size(); ++k)
            system.emission[k] = 1.0 + double(k % 3);
        for (SolverKind kind : kAllSolvers) {
            const SolverResult result = solveOk(f, system, kind, 1e-9);
            ASSERT_TRUE(result.converged) << solverKindName(kind) << " rho " << rho;
            for (std::size_t k = 0; k < result.radiosity.size(); ++k) {
                const double expected = system.emission[k] / (1 - rho);
                EXPECT_NEAR(result.radiosity[k], expected, 1e-6 * expected)
                    << solverKindName(kind) << " rho " << rho << " entry " << k;
            }
        }
    }
}

// The computed view factors of a closed cube (6 faces x 2 triangles, subdivided to 48 patches).
SparseMatrix cubeFormFactors(PatchMesh& patches) {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                      {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    // Inward-facing faces (counter-clockwise seen from inside).
    const std::array<std::array<uint32_t, 4>, 6> faces = {
        {{0, 1, 2, 3}, {4, 7, 6, 5}, {0, 4, 5, 1}, {3, 2, 6, 7}, {0, 3, 7, 4}, {1, 5, 6, 2}}};
    for (const auto& q : faces) {
        mesh.triangles.push_back({q[0], q[1], q[2]});
        mesh.triangles.push_back({q[0], q[2], q[3]});
    }
    mesh.materials.assign(mesh.triangles.size(), 0);
    patches = *buildPatchMesh(mesh, 0.75);
    FormFactorSettings settings;
    settings.progress = false;
    settings.raysPerPair = 0;  // empty convex enclosure: nothing occludes
    auto result = makeCpuBackend()->buildFormFactors(patches, settings);
    EXPECT_TRUE(result.ok());
    return std::move(result->matrix);
}

// The furnace on a computed matrix: its rows sum to s_i in [s_min, s_max] instead of 1, and
// for uniform rho and E the solution lies between E / (1 - rho s_min) and E / (1 - rho s_max)
// (B = sum_b (rho F)^b E is monotone in F's row sums). The hybrid method's row sums on this cube
// are within 3e-6 of 1, which moves B by up to rho 3e-6 / (1 - rho) relative: stated
// tolerances 1e-5, 1e-4 and 1e-3 of E / (1 - rho) for rho = 0.5, 0.9, 0.99.
TEST(Solver, FurnaceOnComputedCubeMatrix) {
    PatchMesh patches;
    const SparseMatrix f = cubeFormFactors(patches);
    ASSERT_GT(f.size, 12u);
    const std::vector<double> sums = rowSums(f);
    const double sMin = *std::min_element(sums.begin(), sums.end());
    const double sMax = *std::max_element(sums.begin(), sums.end());
    // Measured: [0.9999974, 1.0000004] (hybrid, 48 patches, no occluders).
    ASSERT_GT(sMin, 1 - 1e-5);
    ASSERT_LT(sMax, 1 + 1e-5);
    for (const auto& [rho, tolerance] : {std::pair{0.5, 1e-5}, {0.9, 1e-4}, {0.99, 1e-3}}) {
        RadiositySystem system = makeSystem(f.size, 1, {diagonalOperator({rho})});
        system.areas = patches.areas;
        std::fill(system.emission.begin(), system.emission.end(), 1.0);
        const SolverResult result = solveOk(f, system, SolverKind::GaussSeidel, 1e-10);
        for (double b : result.radiosity) {
            EXPECT_NEAR(b, 1 / (1 - rho), tolerance / (1 - rho)) << "rho " << rho;
            EXPECT_GE(b, (1 - 1e-9) / (1 - rho * sMin)) << "rho " << rho;
            EXPECT_LE(b, (1 + 1e-9) / (1 - rho * sMax)) << "rho " << rho;
        }
    }
}

// Against a dense Gaussian elimination of (I - M F) B = E with fluorescent, plain and black
// patches and an open enclosure.
TEST(Solver, MatchesDenseDirectSolve) {
    const auto [f, system] = randomSystem(40, 5, 0.95, 0.5, 7);
    const std::vector<double> expected = denseSolve(f, system);
    for (SolverKind kind : kAllSolvers) {
        const SolverResult result = solveOk(f, system, kind, 1e-13);
        EXPECT_TRUE(result.converged);
        EXPECT_LT(maxRelativeDifference(result.radiosity, expected), 1e-9) << solverKindName(kind);
        EXPECT_LT(result.residual, 1e-13);
    }
}

TEST(Solver, ThreeSolversAgreeAndGaussSeidelIsFastest) {
    // 700 patches: several Gauss-Seidel blocks with in-block couplings.
    const auto [f, system] = randomSystem(700, 16, 0.9, 0.05, 11);
    const SolverResult gs = solveOk(f, system, SolverKind::GaussSeidel, 1e-10);
    const SolverResult jacobi = solveOk(f, system, SolverKind::Jacobi, 1e-10);
    const SolverResult southwell = solveOk(f, system, SolverKind::Southwell, 1e-10);
    // The residual 1e-10 bounds each answer's error by about 1e-10 / (1 - 0.9) in the power
    // norm; single entries (some dim) move by more.
    const SolverResult exact = solveOk(f, system, SolverKind::Jacobi, 1e-14);
    for (const SolverResult* result : {&gs, &jacobi, &southwell})
        EXPECT_LT(maxRelativeDifference(result->radiosity, exact.radiosity), 2e-8);
    EXPECT_LT(gs.iterations, jacobi.iterations);
}

// The blocked parallel sweep is exactly Gauss-Seidel: one sweep equals the textbook sweep (rows
// in order, each gathering the current B in place) on 700 patches (three 256-row blocks).
TEST(Solver, OneSweepIsTheTextbookGaussSeidelSweep) {
    const auto [f, system] = randomSystem(700, 3, 0.9, 0.05, 17);
    SolverSettings settings;
    settings.tolerance = 1e-30;  // double precision throughout
    settings.maxIterations = 1;
    auto result = solveRadiosity(f, system, settings);
    ASSERT_TRUE(result.ok());
    std::vector<double> b = system.emission;
    const std::size_t m = 3;
    for (uint32_t i = 0; i < system.patchCount; ++i) {
        const MaterialOperator& op = system.operators[system.patchOperator[i]];
        if (op.isZero) continue;
        std::vector<double> g(m, 0);
        for (uint64_t p = f.rowOffsets[i]; p < f.rowOffsets[i + 1]; ++p)
            for (std::size_t k = 0; k < m; ++k)
                g[k] += f.values[p] * b[f.columns[p] * m + k];
        for (std::size_t o = 0; o < m; ++o) {
            double sum = system.emission[i * m + o];
            for (std::size_t k = 0; k < m; ++k)
                sum += op.matrix(o, k) * g[k];
            b[i * m + o] = sum;
        }
    }
    EXPECT_LT(maxRelativeDifference(result->radiosity, b), 1e-13);
}

// Gauss-Seidel adds the rest of the geometric series once its changes shrink by a settled
// ratio: a white furnace of reflectance 0.99 in a closed cube, whose error shrinks by about rho
// a sweep (Jacobi's sweeps, which are not extrapolated, need thousands), converges in a few
// dozen sweeps, to its exact solution E / (1 - rho).
TEST(Solver, GaussSeidelExtrapolatesTheGeometricTail) {
    PatchMesh patches;
    const SparseMatrix f = cubeFormFactors(patches);
    const double rho = 0.99;
    RadiositySystem system = makeSystem(f.size, 1, {diagonalOperator({rho})});
    system.areas = patches.areas;
    std::fill(system.emission.begin(), system.emission.end(), 1.0);
    const SolverResult jacobi = solveOk(f, system, SolverKind::Jacobi, 1e-10);
    EXPECT_GT(jacobi.iterations, 1000);
    const SolverResult gs = solveOk(f, system, SolverKind::GaussSeidel, 1e-10);
    EXPECT_TRUE(gs.converged);
    EXPECT_LT(gs.iterations, 40);
    for (double b : gs.radiosity)
        EXPECT_NEAR(b, 1 / (1 - rho), 1e-3 / (1 - rho));
}

// Jacobi from B^0 = E: B^k = E + M F B^(k-1) = sum_{b=0..k} (M F)^b E, the k-bounce Neumann sum.
TEST(Solver, JacobiIterateKIsTheKBounceNeumannSum) {
    const auto [f, system] = randomSystem(30, 4, 0.9, 0.5, 3);
    const std::size_t size = system.emission.size(), m = system.wavelengthCount;
    std::vector<std::vector<double>> iterates;
    SolverSettings settings;
    settings.kind = SolverKind::Jacobi;
    settings.tolerance = 1e-30;
    settings.maxIterations = 6;
    settings.onIteration = [&](int, std::span<const double> b) {
        iterates.emplace_back(b.begin(), b.end());
    };
    auto result = solveRadiosity(f, system, settings);
    ASSERT_TRUE(result.ok());
    EXPECT_FALSE(result->converged);
    EXPECT_NE(result->warning.find("not converged after 6 iterations"), std::string::npos);
    ASSERT_EQ(iterates.size(), 6u);
    // The Neumann terms, computed densely: term_b = M F term_(b-1).
    std::vector<double> term = system.emission, sum = system.emission;
    for (int k = 1; k <= 6; ++k) {
        std::vector<double> next(size, 0);
        for (uint32_t i = 0; i < system.patchCount; ++i) {
            std::vector<double> g(m, 0);
            for (uint64_t p = f.rowOffsets[i]; p < f.rowOffsets[i + 1]; ++p)
                for (std::size_t l = 0; l < m; ++l)
                    g[l] += f.values[p] * term[f.columns[p] * m + l];
            const MaterialOperator& op = system.operators[system.patchOperator[i]];
            for (std::size_t o = 0; o < m; ++o)
                for (std::size_t l = 0; l < m; ++l)
                    next[i * m + o] += op.matrix(o, l) * g[l];
        }
        term = next;
        for (std::size_t e = 0; e < size; ++e)
            sum[e] += term[e];
        EXPECT_LT(maxRelativeDifference(iterates[k - 1], sum), 1e-12) << "bounce " << k;
    }
}

// Closed furnace of one fluorescent material: the uniform solution solves B = E + M B, so
// B = (I - M)^-1 E (M lower-triangular: forward substitution by hand below).
TEST(Solver, FluorescentFurnaceIsInverseOfIMinusM) {
    const std::vector<double> m3 = {0.5, 0,   0,  //
                                    0.3, 0.4, 0,  //
                                    0.1, 0.2, 0.6};
    RadiositySystem system = makeSystem(9, 3, {matrixOperator(3, m3)});
    const double e[3] = {2, 1, 0.5};
    for (uint32_t i = 0; i < 9; ++i)
        std::copy(e, e + 3, system.emission.begin() + i * 3);
    // (I - M) B = E: B0 = 2 / 0.5 = 4; B1 = (1 + 0.3 B0) / 0.6; B2 = (0.5 + 0.1 B0 + 0.2 B1) / 0.4.
    const double b0 = 4, b1 = (1 + 0.3 * b0) / 0.6, b2 = (0.5 + 0.1 * b0 + 0.2 * b1) / 0.4;
    for (SolverKind kind : kAllSolvers) {
        const SolverResult result = solveOk(furnaceMatrix(9), system, kind, 1e-10);
        for (uint32_t i = 0; i < 9; ++i) {
            EXPECT_NEAR(result.radiosity[i * 3 + 0], b0, 1e-8 * b0) << solverKindName(kind);
            EXPECT_NEAR(result.radiosity[i * 3 + 1], b1, 1e-8 * b1) << solverKindName(kind);
            EXPECT_NEAR(result.radiosity[i * 3 + 2], b2, 1e-8 * b2) << solverKindName(kind);
        }
    }
}

TEST(Solver, SameBitsForAnyThreadCount) {
    const auto [f, system] = randomSystem(700, 7, 0.9, 0.05, 5);
    for (SolverKind kind : kAllSolvers) {
        const SolverResult one = solveOk(f, system, kind, 1e-8, 1);
        const SolverResult two = solveOk(f, system, kind, 1e-8, 2);
        EXPECT_EQ(one.radiosity, two.radiosity) << solverKindName(kind);
        EXPECT_EQ(one.iterations, two.iterations);
    }
}

// At the default tolerance the gathers read B as float (kMixedPrecisionMinTolerance): the true
// residual (computed in double) still meets the tolerance, the answer is within what that
// residual allows of the double-precision one, and threads do not change the bits. m = 4, 8
// and 16 take the AVX2, AVX-512 and AVX-512 x 2 kernels where the CPU has them.
TEST(Solver, MixedPrecisionMeetsTheToleranceForAnyThreadCount) {
    for (std::size_t m : {4, 8, 16}) {
        const auto [f, system] = randomSystem(700, m, 0.9, 0.05, 13);
        const SolverResult exact = solveOk(f, system, SolverKind::GaussSeidel, 1e-12);
        const SolverResult one = solveOk(f, system, SolverKind::GaussSeidel, 1e-4, 1);
        const SolverResult two = solveOk(f, system, SolverKind::GaussSeidel, 1e-4, 2);
        EXPECT_TRUE(one.converged);
        EXPECT_LE(one.residual, 1e-4);
        // Error <= residual / (1 - gain x row sum) = 1e-4 / (1 - 0.9 x 0.9) < 1e-3 in the
        // power norm; per entry allow 1e-2.
        EXPECT_LT(powerNorm(system, one.radiosity) > 0
                      ? maxRelativeDifference(one.radiosity, exact.radiosity)
                      : 1,
                  1e-2)
            << "m " << m;
        EXPECT_EQ(one.radiosity, two.radiosity) << "m " << m;
    }
}

TEST(Solver, BlackPatchesKeepTheirEmission) {
    const auto [f, system] = randomSystem(40, 3, 0.9, 0.5, 9);
    const SolverResult result = solveOk(f, system, SolverKind::GaussSeidel);
    for (uint32_t i = 0; i < system.patchCount; ++i) {
        if (system.patchOperator[i] != 2) continue;  // operator 2 is zero
        for (std::size_t k = 0; k < 3; ++k)
            EXPECT_EQ(result.radiosity[i * 3 + k], system.emission[i * 3 + k]);
    }
}

TEST(Solver, NoEmissionGivesZero) {
    RadiositySystem system = makeSystem(9, 2, {diagonalOperator({0.5, 0.5})});
    const SolverResult result = solveOk(furnaceMatrix(9), system, SolverKind::GaussSeidel);
    EXPECT_TRUE(result.converged);
    EXPECT_EQ(result.iterations, 0);
    for (double b : result.radiosity)
        EXPECT_EQ(b, 0);
}

// rho = 1 in a closed enclosure: nothing is ever absorbed, B = E / (1 - 1) is infinite.
TEST(Solver, LosslessEnclosureIsRefusedUpFront) {
    RadiositySystem system = makeSystem(9, 2, {diagonalOperator({1.0, 0.5})});
    system.operators[0].materialNames = {"perfect_white"};
    system.emission[0] = 1;
    auto result = solveRadiosity(furnaceMatrix(9), system, SolverSettings{});
    ASSERT_FALSE(result.ok());
    EXPECT_NE(result.error().message.find("no finite solution"), std::string::npos);
    EXPECT_NE(result.error().message.find("perfect_white: 9 patches (0, 1, 2, 3, 4, ...)"),
              std::string::npos)
        << result.error().message;
}

// Row sums of 1.25 (a bad matrix) with rho = 0.9 on most patches: gain 1.125 per bounce; a few
// black patches keep it from being refused up front, so the growth must be caught.
TEST(Solver, DivergenceIsDetectedAndExplained) {
    std::vector<double> dense(9 * 9, 0);
    for (uint32_t i = 0; i < 9; ++i)
        for (uint32_t j = 0; j < 9; ++j)
            if (i != j) dense[i * 9 + j] = 1.25 / 8;
    const SparseMatrix f = solvertest::sparseFromDense(9, dense);
    RadiositySystem system = makeSystem(9, 1, {diagonalOperator({0.95}), diagonalOperator({0.0})});
    system.operators[0].materialNames = {"glowing"};
    system.patchOperator[8] = 1;
    system.emission[0] = 1;
    for (SolverKind kind : kAllSolvers) {
        SolverSettings settings;
        settings.kind = kind;
        auto result = solveRadiosity(f, system, settings);
        ASSERT_FALSE(result.ok()) << solverKindName(kind);
        EXPECT_NE(result.error().message.find("diverge"), std::string::npos);
        EXPECT_NE(result.error().message.find("material glowing: 8 patches (0, 1, 2, 3, 4, ...)"),
                  std::string::npos)
            << result.error().message;
    }
}

TEST(Solver, ParsesNames) {
    SolverKind kind;
    EXPECT_TRUE(parseSolverKind("southwell", kind));
    EXPECT_EQ(kind, SolverKind::Southwell);
    EXPECT_STREQ(solverKindName(SolverKind::GaussSeidel), "gauss-seidel");
    EXPECT_FALSE(parseSolverKind("conjugate-gradient", kind));
}

}  // namespace
}  // namespace daisy
