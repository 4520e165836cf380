#pragma once
// Solvers of the spectral radiosity equation (DESIGN.md sections 2 and 6)
//     B = E + M F B,   i.e.  B_i = E_i + M_mat(i) G_i,   G_i = sum_j F_ij B_j,
// for all m wavelength samples at once. B, E and G are patchCount x m, row-major, in double, so
// one stored F_ij updates m contiguous values (the inner loop vectorises over m).
//
// - jacobi: B^0 = E, B^k = E + M F B^(k-1): iterate k is the k-bounce Neumann sum
//   sum_{b<=k} (M F)^b E (Neumann series; Cohen & Wallace 1993, "Radiosity and Realistic Image
//   Synthesis", chapter 5). Rows in parallel.
// - gauss-seidel (default): rows in order, each using the rows already updated this sweep
//   (Cohen & Wallace chapter 5). Parallel and exact: rows are taken in fixed blocks; the
//   part of a block's gathers that reads other blocks (earlier blocks: this sweep's values,
//   later ones: the last sweep's) runs in parallel, the in-block remainder row by row.
//   Extrapolated: once a wavelength's changes shrink by a settled ratio r from sweep to sweep
//   (the error then lies along the iteration's dominant eigenvector, and each later sweep would
//   add r times the last change), the rest of that geometric series, delta r / (1 - r), is
//   added at once (Aitken's extrapolation, per wavelength; the "ambient term" of Cohen et al.
//   1988, below, rests on the same estimate). The stopping rule below is unchanged: the answer
//   still meets the tolerance on its true residual. Measured: the hierarchical transport,
//   whose far links are swept as in Jacobi, 13 -> 7-8 sweeps; a white furnace of reflectance
//   0.99 in a cube, 952 -> 22. Jacobi is not extrapolated: its iterate k stays the k-bounce sum.
// - southwell: progressive shooting of the largest unshot power (Cohen et al. 1988, "A
//   progressive refinement approach to fast radiosity image generation", SIGGRAPH), one
//   iteration = patchCount shots. Uses the transpose of F (column access).
// Mixed precision: with tolerance >= kMixedPrecisionMinTolerance the gathers read B rounded to
// float and sum short runs of products in float before adding them to double sums (a third of
// the vector work where the CPU has AVX2/AVX-512); B, E + M G and the residual stay double.
// The true residual that stops the solve is always computed in double, so the answer meets
// the tolerance; the float rounding (~1e-7, at worst ~1e-6 relative) stays ten times under it.
// Smaller tolerances read and sum B in double throughout.
// Every solver gives the same bits for any thread count: each row's sum runs in a fixed order
// and norms are summed sequentially over per-row parts.
//
// Norm: the power norm ||X|| = sum_i A_i sum_k w_k |X_ik| (A_i patch area, w_k the set's bin
// width), i.e. watts of spectral exitance. Stopping: when the change of an iteration relative to
// ||B||, times the last contraction ratio of the changes (a prediction of the new iterate's
// residual; for Jacobi the change is exactly the previous iterate's residual), falls under the
// tolerance, the true relative residual ||E + M F B - B|| / ||B|| is computed (one gather, in
// double); the solve stops when that is under `tolerance`, or at maxIterations.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "core/cancel.h"
#include "core/expected.h"
#include "radiosity/radiosity_system.h"
#include "radiosity/sparse_matrix.h"

namespace daisy {

enum class SolverKind { GaussSeidel, Jacobi, Southwell };
// "gauss-seidel", "jacobi", "southwell"; false for anything else.
bool parseSolverKind(const std::string& name, SolverKind& kind);
const char* solverKindName(SolverKind kind);
// Every solver name, the default (gauss-seidel) first.
std::vector<std::string> solverKindNames();

// Tolerances at or above this solve in mixed precision (see the file comment).
inline constexpr double kMixedPrecisionMinTolerance = 1e-5;

struct SolverSettings {
    SolverKind kind = SolverKind::GaussSeidel;
    double tolerance = 1e-4;  // relative residual in the power norm
    int maxIterations = 1000;  // >= 0; 0 returns B = E
    int threads = 0;  // 0 = all hardware threads
    // Called after every iteration with its number (1-based) and the iterate (n x m); optional
    // (the viewer steps through Jacobi's bounces with it).
    std::function<void(int iteration, std::span<const double> radiosity)> onIteration;
    // Warm start: the first iterate (n x m, e.g. the last solution before a material edit);
    // empty = B^0 = E. Southwell shoots the start's residual (see solveRadiosity).
    std::span<const double> initialRadiosity;
    // Polled between iterations and every Gauss-Seidel block (a few ms): when cancelled the
    // solve returns at once with cancelled = true and the last iterate.
    const CancelToken* cancel = nullptr;
    // What every solve of the same F derives from it, when the caller keeps it (the session
    // does): F's row sums (size n) and its transpose (Southwell). Empty / null = computed here.
    std::span<const double> rowSums;
    const SparseMatrix* transposed = nullptr;
    // The part of G = T B that F does not hold (the hierarchical transport's far links,
    // radiosity/hierarchical_transport.h): farGather(B, G) writes it for the iterate B (n x m).
    // It is computed at the start of every iteration and added to each row's gather, so
    // Gauss-Seidel takes it from the last sweep's B; the residual uses the full T B. Null: F is
    // all of T. Southwell, which shoots along F's columns, refuses it.
    std::function<void(std::span<const double> radiosity, std::span<double> gathered)> farGather;
};

struct SolverResult {
    std::vector<double> radiosity;  // B, patchCount x m
    std::vector<double> gathered;  // G = F B for the returned B (energy bookkeeping uses it)
    int iterations = 0;
    double residual = 0;  // true relative residual of the returned B
    bool converged = false;  // residual <= tolerance
    bool cancelled = false;  // stopped by settings.cancel; radiosity is the last iterate
    double seconds = 0;  // wall time of the iterations and the final residual
    // ||B^k - B^(k-1)|| / ||B^k|| per iteration (southwell: ||unshot|| / ||B||)
    std::vector<double> changeHistory;
    std::string warning;  // set when not converged: why, which materials and patches
};

// Patches that can amplify light: maxPowerGain of their operator times their row sum >= 1
// (DESIGN.md section 6). Grouped by operator for messages.
struct ConvergenceRisk {
    std::vector<uint32_t> patches;  // ascending
    std::string
        description;  // "materials a, b: 12 patches (0, 3, 7, ...) gain x row sum up to 1.02"
};
ConvergenceRisk findConvergenceRisk(const SparseMatrix& formFactors, const RadiositySystem& system);

// Solves. Errors (the scene's fault, exit status 2): F and the system disagree in size; every
// patch amplifies light (no absorption, no opening: the solution is infinite); the iteration
// diverges (the change grows for kDivergenceIterations iterations in a row, or B stops being
// finite); memory for the solver's work arrays cannot be had. Reaching maxIterations is not an
// error: converged = false and `warning` says why; neither is cancellation (cancelled = true).
inline constexpr int kDivergenceIterations = 6;
Expected<SolverResult> solveRadiosity(const SparseMatrix& formFactors,
                                      const RadiositySystem& system,
                                      const SolverSettings& settings);

// G = F B (n x m) in double, rows in parallel on `threads` threads (0: the calling arena's);
// each row is summed in a fixed order, so the result does not depend on the thread count.
void gatherAll(const SparseMatrix& formFactors, std::span<const double> radiosity,
               std::size_t wavelengthCount, std::span<double> gathered, int threads = 0);

// ||E + M G - B|| / ||B|| for G = F B already computed; 0 when B = 0.
double relativeResidual(const RadiositySystem& system, std::span<const double> radiosity,
                        std::span<const double> gathered);

// The power norm above.
double powerNorm(const RadiositySystem& system, std::span<const double> values);

}  // namespace daisy
