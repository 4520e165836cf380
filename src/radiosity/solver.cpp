#include "radiosity/solver.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <memory>
#include <new>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/memory.h"
#include "core/strings.h"
#include "core/timer.h"
#include "radiosity/gather_kernels.h"

namespace daisy {
namespace {

// Gauss-Seidel block: rows per sequential in-block pass. Fixed (not derived from the thread
// count) so the summation order, and hence every bit of the result, is the same on any machine.
constexpr uint32_t kBlockRows = 256;
// Rows per parallel task: a row of a 7,712-patch scene has ~4,000 entries x m wavelengths.
constexpr uint32_t kRowGrain = 8;
// Targets per parallel task of one Southwell shot.
constexpr std::size_t kShotGrain = 512;
constexpr std::size_t kHugePage = std::size_t(2) << 20;
// Extrapolation (see solver.h): a wavelength's contraction ratio counts as settled when its
// last two ratios differ by at most this share of 1 - ratio, so that the extrapolation factor
// ratio / (1 - ratio) is known to about this share.
constexpr double kSettledRatio = 0.1;

// A_i sum_k w_k |x_k|.
double rowPower(const RadiositySystem& system, uint32_t row, const double* x) {
    double sum = 0;
    for (std::size_t k = 0; k < system.wavelengthCount; ++k)
        sum += system.binWidthsNm[k] * std::abs(x[k]);
    return system.areas[row] * sum;
}

double rowPowerOfDifference(const RadiositySystem& system, uint32_t row, const double* a,
                            const double* b) {
    double sum = 0;
    for (std::size_t k = 0; k < system.wavelengthCount; ++k)
        sum += system.binWidthsNm[k] * std::abs(a[k] - b[k]);
    return system.areas[row] * sum;
}

double sequentialSum(const std::vector<double>& parts) {
    double sum = 0;
    for (double part : parts)
        sum += part;
    return sum;
}

std::vector<double> parallelRowSums(const SparseMatrix& f) {
    std::vector<double> sums(f.size, 0);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, f.size, 256),
                      [&](const tbb::blocked_range<uint32_t>& range) {
                          for (uint32_t i = range.begin(); i != range.end(); ++i) {
                              // Four interleaved sums: no chain of dependent adds.
                              double part[4] = {0, 0, 0, 0};
                              const uint64_t end = f.rowOffsets[i + 1];
                              uint64_t p = f.rowOffsets[i];
                              for (; p + 4 <= end; p += 4)
                                  for (int u = 0; u < 4; ++u)
                                      part[u] += f.values[p + u];
                              for (; p < end; ++p)
                                  part[0] += f.values[p];
                              sums[i] = (part[0] + part[1]) + (part[2] + part[3]);
                          }
                      });
    return sums;
}

ConvergenceRisk riskFromRowSums(const RadiositySystem& system, std::span<const double> sums) {
    ConvergenceRisk risk;
    struct Group {
        std::vector<uint32_t> patches;
        double worst = 0;
    };
    std::map<uint32_t, Group> groups;
    for (uint32_t i = 0; i < system.patchCount; ++i) {
        const MaterialOperator& op = system.operators[system.patchOperator[i]];
        const double gain = op.maxPowerGain * sums[i];
        if (gain < 1) continue;
        risk.patches.push_back(i);
        Group& group = groups[system.patchOperator[i]];
        group.patches.push_back(i);
        group.worst = std::max(group.worst, gain);
    }
    for (const auto& [index, group] : groups) {
        std::string names;
        for (const std::string& name : system.operators[index].materialNames)
            names += (names.empty() ? "" : ", ") + name;
        std::string ids;
        for (std::size_t k = 0; k < std::min<std::size_t>(group.patches.size(), 5); ++k)
            ids += (k ? ", " : "") + std::to_string(group.patches[k]);
        if (group.patches.size() > 5) ids += ", ...";
        if (!risk.description.empty()) risk.description += "; ";
        risk.description +=
            concat("material ", names.empty() ? "(unnamed)" : names, ": ",
                   formatCount(group.patches.size()), " patches (", ids,
                   ") with reflectance x row sum up to ", formatNumber(group.worst, 6));
    }
    return risk;
}

class Solver {
public:
    Solver(const SparseMatrix& f, const RadiositySystem& system, const SolverSettings& settings)
        : f_(f),
          system_(system),
          settings_(settings),
          m_(system.wavelengthCount),
          mixed_(settings.tolerance >= kMixedPrecisionMinTolerance),
          accumulateDouble_(accumulateFor<double>(system.wavelengthCount)),
          accumulateFloat_(accumulateFor<float>(system.wavelengthCount)) {
        active_.resize(system.patchCount);
        for (uint32_t i = 0; i < system.patchCount; ++i)
            active_[i] = !system.operators[system.patchOperator[i]].isZero &&
                (f.rowLength(i) > 0 || settings.farGather);
    }

    Expected<SolverResult> run();

private:
    const double* rowOf(const std::vector<double>& x, uint32_t i) const {
        return x.data() + i * m_;
    }
    double* rowOf(std::vector<double>& x, uint32_t i) const { return x.data() + i * m_; }
    const MaterialOperator& op(uint32_t i) const {
        return system_.operators[system_.patchOperator[i]];
    }
    // acc += sum over entries [begin, end) of F_ij B_j, B read from the mirror when mixed_.
    void gatherRow(uint64_t begin, uint64_t end, double* acc) const {
        if (mixed_) {
            accumulateFloat_(f_.columns.data(), f_.values.data(), begin, end, mirror_, m_, acc);
        } else {
            accumulateDouble_(f_.columns.data(), f_.values.data(), begin, end, b_.data(), m_, acc);
        }
    }
    // The start of row i's gather: its far part (settings_.farGather) or 0.
    void startRow(uint32_t i, double* g) const {
        if (far_.empty()) {
            std::fill(g, g + m_, 0.0);
        } else {
            std::copy_n(rowOf(far_, i), m_, g);
        }
    }
    // far_ = the far part of T B for the current B (no work without settings_.farGather).
    void refreshFar() {
        if (settings_.farGather) settings_.farGather(b_, far_);
    }
    // G = T B for the current B: F B plus the far part.
    void gatherFull() {
        gatherAll(f_, b_, m_, g_, 0);
        if (!settings_.farGather) return;
        refreshFar();
        for (std::size_t e = 0; e < g_.size(); ++e)
            g_[e] += far_[e];
    }
    // Values under float's smallest normal become 0, as the float kernels would treat them
    // (denormals-are-zero), without the slow conversion to a denormal.
    void refreshMirror(uint32_t begin, uint32_t end) {
        if (!mixed_) return;
        for (std::size_t e = begin * m_; e < end * m_; ++e) {
            const double value = b_[e];
            mirror_[e] = std::abs(value) < double(std::numeric_limits<float>::min())
                ? 0.0f
                : static_cast<float>(value);
        }
    }
    double jacobiIteration();
    double gaussSeidelIteration();
    // delta_'s row i = next - last (Gauss-Seidel's extrapolation).
    void recordDelta(uint32_t i, const double* next, const double* last) {
        float* d = delta_.data() + std::size_t(i) * m_;
        for (std::size_t k = 0; k < m_; ++k)
            d[k] = static_cast<float>(next[k] - last[k]);
    }
    bool extrapolate();
    double southwellIteration();
    bool cancelRequested() {
        cancelled_ = cancelled_ || isCancelled(settings_.cancel);
        return cancelled_;
    }

    const SparseMatrix& f_;
    const RadiositySystem& system_;
    const SolverSettings& settings_;
    std::size_t m_;
    // Mixed precision: B is read as float (a mirror refreshed as B changes) while the sums and
    // B itself stay double. See kMixedPrecisionMinTolerance.
    bool mixed_;
    AccumulateFn<double> accumulateDouble_;
    AccumulateFn<float> accumulateFloat_;
    std::unique_ptr<float, void (*)(void*)> mirrorStorage_{nullptr, std::free};
    float* mirror_ = nullptr;
    std::vector<uint8_t> active_;  // rows that gather: non-zero operator and a non-empty F row
    std::vector<double> b_, next_, g_, rowChange_;
    std::vector<double> far_;  // the far part of T B (settings_.farGather), n x m; else empty
    // Extrapolation (Gauss-Seidel): the last sweep's B^k - B^(k-1) (n x m), and per
    // wavelength the last sweep's change sum_i A_i |delta_i| and contraction ratio (< 0: none
    // yet), and how many sweeps since the start or the last extrapolation were measured.
    std::vector<float> delta_;
    std::vector<double> waveChange_, waveRatio_;
    int measuredSweeps_ = 0;
    // Gauss-Seidel: per row of the current block, its in-block entry range; one row's new B.
    std::vector<std::array<uint64_t, 2>> inBlock_;
    std::vector<double> scratch_;
    // Southwell: unshot radiosity, its power per patch, and F transposed (row i = column i).
    std::vector<double> unshot_, unshotPower_;
    SparseMatrix ownTransposed_;
    const SparseMatrix* transposed_ = nullptr;  // settings_.transposed or &ownTransposed_
    bool cancelled_ = false;
};

// B^k = E + M F B^(k-1) for every row at once. Returns ||B^k - B^(k-1)||.
double Solver::jacobiIteration() {
    refreshFar();
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, system_.patchCount, kRowGrain),
                      [&](const tbb::blocked_range<uint32_t>& range) {
                          for (uint32_t i = range.begin(); i != range.end(); ++i) {
                              if (!active_[i]) continue;
                              double* g = rowOf(g_, i);
                              startRow(i, g);
                              gatherRow(f_.rowOffsets[i], f_.rowOffsets[i + 1], g);
                              double* out = rowOf(next_, i);
                              applyOperator(op(i), g, out, system_.emissionRow(i));
                              rowChange_[i] = rowPowerOfDifference(system_, i, out, rowOf(b_, i));
                          }
                      });
    b_.swap(next_);
    refreshMirror(0, system_.patchCount);
    return sequentialSum(rowChange_);
}

// One exact Gauss-Seidel sweep in row order, in blocks of kBlockRows: first, in parallel, each
// row of the block gathers from the columns outside the block (earlier blocks already hold this
// sweep's values, later ones the last sweep's; nothing writes B meanwhile); then the block's
// rows, in order, add their in-block columns and update B in place.
double Solver::gaussSeidelIteration() {
    const uint32_t n = system_.patchCount;
    refreshFar();
    for (uint32_t blockBegin = 0; blockBegin < n; blockBegin += kBlockRows) {
        if (cancelRequested()) break;
        const uint32_t blockEnd = std::min(n, blockBegin + kBlockRows);
        tbb::parallel_for(
            tbb::blocked_range<uint32_t>(blockBegin, blockEnd, kRowGrain),
            [&](const tbb::blocked_range<uint32_t>& range) {
                for (uint32_t i = range.begin(); i != range.end(); ++i) {
                    if (!active_[i]) continue;
                    double* g = rowOf(g_, i);
                    startRow(i, g);
                    const uint64_t rowBegin = f_.rowOffsets[i], rowEnd = f_.rowOffsets[i + 1];
                    const uint32_t* columns = f_.columns.data();
                    const uint64_t inBegin =
                        std::lower_bound(columns + rowBegin, columns + rowEnd, blockBegin) -
                        columns;
                    const uint64_t inEnd =
                        std::lower_bound(columns + inBegin, columns + rowEnd, blockEnd) - columns;
                    gatherRow(rowBegin, inBegin, g);
                    gatherRow(inEnd, rowEnd, g);
                    // Remember where the in-block part is for the sequential pass.
                    inBlock_[i - blockBegin] = {inBegin, inEnd};
                }
            });
        for (uint32_t i = blockBegin; i < blockEnd; ++i) {
            if (!active_[i]) continue;
            double* g = rowOf(g_, i);
            const auto [inBegin, inEnd] = inBlock_[i - blockBegin];
            gatherRow(inBegin, inEnd, g);
            double* row = rowOf(b_, i);
            applyOperator(op(i), g, scratch_.data(), system_.emissionRow(i));
            rowChange_[i] = rowPowerOfDifference(system_, i, scratch_.data(), row);
            recordDelta(i, scratch_.data(), row);
            std::copy(scratch_.begin(), scratch_.end(), row);
            refreshMirror(i, i + 1);
        }
    }
    return sequentialSum(rowChange_);
}

// After a sweep: per wavelength, its change and contraction ratio; where the ratio r has
// settled (kSettledRatio), B += delta r / (1 - r) for that wavelength, the rest of the
// geometric series the sweeps would add if every later change were r times the one before.
// Returns whether B moved; the changes of the next sweep then start a new series.
bool Solver::extrapolate() {
    const uint32_t n = system_.patchCount;
    std::vector<double> change(m_, 0.0);
    for (uint32_t i = 0; i < n; ++i) {
        if (!active_[i]) continue;
        const float* d = delta_.data() + std::size_t(i) * m_;
        for (std::size_t k = 0; k < m_; ++k)
            change[k] += system_.areas[i] * std::abs(double(d[k]));
    }
    std::vector<double> factor(m_, 0.0);
    bool any = false;
    for (std::size_t k = 0; k < m_; ++k) {
        const double ratio =
            measuredSweeps_ >= 1 && waveChange_[k] > 0 ? change[k] / waveChange_[k] : -1;
        if (measuredSweeps_ >= 2 && ratio > 0 && ratio < 1 && waveRatio_[k] > 0 &&
            std::abs(ratio - waveRatio_[k]) <= kSettledRatio * (1 - ratio)) {
            factor[k] = ratio / (1 - ratio);
            any = true;
        }
        waveRatio_[k] = ratio;
        waveChange_[k] = change[k];
    }
    ++measuredSweeps_;
    if (!any) return false;
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 1024),
                      [&](const tbb::blocked_range<uint32_t>& range) {
                          for (uint32_t i = range.begin(); i != range.end(); ++i) {
                              if (!active_[i]) continue;
                              double* b = rowOf(b_, i);
                              const float* d = delta_.data() + std::size_t(i) * m_;
                              for (std::size_t k = 0; k < m_; ++k)
                                  b[k] += factor[k] * double(d[k]);
                          }
                      });
    refreshMirror(0, n);
    measuredSweeps_ = 0;
    return true;
}

// patchCount shots, each from the patch with the most unshot power (ties: lowest index).
// Shooting u from patch i adds, to every patch j that sees i, delta = M_j F_ji u to both its
// radiosity and its unshot radiosity; this keeps B = E + M F (B - unshot). Returns ||unshot||.
double Solver::southwellIteration() {
    const uint32_t n = system_.patchCount;
    std::vector<double> shot(m_);
    for (uint32_t shotIndex = 0; shotIndex < n; ++shotIndex) {
        if (shotIndex % 64 == 0 && cancelRequested()) break;
        const auto best = std::max_element(unshotPower_.begin(), unshotPower_.end());
        if (*best <= 0) break;
        const uint32_t i = static_cast<uint32_t>(best - unshotPower_.begin());
        double* u = rowOf(unshot_, i);
        std::copy(u, u + m_, shot.begin());
        std::fill(u, u + m_, 0.0);
        unshotPower_[i] = 0;
        const std::span<const uint32_t> targets = transposed_->rowColumns(i);
        const std::span<const float> factors = transposed_->rowValues(i);
        // The targets of one shot are distinct patches: updated in parallel, each on its own.
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, targets.size(), kShotGrain),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              std::vector<double> received(m_), delta(m_);
                              for (std::size_t p = range.begin(); p != range.end(); ++p) {
                                  const uint32_t j = targets[p];
                                  const MaterialOperator& target = op(j);
                                  if (target.isZero) continue;
                                  const double f = factors[p];
                                  for (std::size_t k = 0; k < m_; ++k)
                                      received[k] = f * shot[k];
                                  applyOperator(target, received.data(), delta.data());
                                  double* bj = rowOf(b_, j);
                                  double* uj = rowOf(unshot_, j);
                                  for (std::size_t k = 0; k < m_; ++k) {
                                      bj[k] += delta[k];
                                      uj[k] += delta[k];
                                  }
                                  unshotPower_[j] = rowPower(system_, j, uj);
                              }
                          });
    }
    return sequentialSum(unshotPower_);
}

Expected<SolverResult> Solver::run() {
    const auto start = Clock::now();
    const uint32_t n = system_.patchCount;
    SolverResult result;
    const bool warm = !settings_.initialRadiosity.empty();
    if (warm) {
        b_.assign(settings_.initialRadiosity.begin(), settings_.initialRadiosity.end());
    } else {
        b_ = system_.emission;
    }
    if (mixed_) {
        // Gathers read B rows in random order: on 2 MiB pages the whole mirror of a 7,712-patch,
        // 16-sample scene (0.5 MB) needs one TLB entry instead of 121 (measured: a third less
        // time per gather). A 16-sample row is one 64-byte cache line.
        const std::size_t bytes =
            (b_.size() * sizeof(float) + kHugePage - 1) / kHugePage * kHugePage;
        mirrorStorage_.reset(static_cast<float*>(std::aligned_alloc(kHugePage, bytes)));
        if (!mirrorStorage_) {
            return Error{concat("out of memory: the solver's float copy of B needs ",
                                formatBytes(double(bytes)))};
        }
        adviseHugePages(mirrorStorage_.get(), bytes);
        mirror_ = mirrorStorage_.get();
        refreshMirror(0, n);
    }
    g_.assign(std::size_t(n) * m_, 0.0);
    if (settings_.farGather) far_.assign(std::size_t(n) * m_, 0.0);
    rowChange_.assign(n, 0.0);

    std::vector<double> ownSums;
    if (settings_.rowSums.empty()) ownSums = parallelRowSums(f_);
    const std::span<const double> sums =
        settings_.rowSums.empty() ? std::span<const double>(ownSums) : settings_.rowSums;
    const ConvergenceRisk risk = riskFromRowSums(system_, sums);
    if (n > 0 && risk.patches.size() == n) {
        return Error{
            concat("the radiosity equation has no finite solution: every patch "
                   "reflects or re-emits at least all the light that reaches it and "
                   "none escapes (",
                   risk.description, ")")};
    }

    if (settings_.kind == SolverKind::GaussSeidel) {
        delta_.assign(std::size_t(n) * m_, 0.0f);
        waveChange_.assign(m_, 0.0);
        waveRatio_.assign(m_, -1.0);
    }
    switch (settings_.kind) {
        case SolverKind::Jacobi:
            next_ = b_;
            break;
        case SolverKind::GaussSeidel:
            inBlock_.resize(kBlockRows);
            scratch_.resize(m_);
            break;
        case SolverKind::Southwell:
            if (settings_.transposed) {
                transposed_ = settings_.transposed;
            } else {
                ownTransposed_ = transpose(f_);
                transposed_ = &ownTransposed_;
            }
            unshot_ = system_.emission;
            if (warm) {
                // Shoot the start's residual r = E + M F B0 - B0: B = B0 + X with
                // X = r + M F X, started (as from E) at X = r with r unshot.
                gatherAll(f_, b_, m_, g_, 0);
                for (uint32_t i = 0; i < n; ++i) {
                    double* u = rowOf(unshot_, i);
                    applyOperator(op(i), rowOf(g_, i), u, system_.emissionRow(i));
                    double* b = rowOf(b_, i);
                    for (std::size_t k = 0; k < m_; ++k) {
                        u[k] -= b[k];
                        b[k] += u[k];
                    }
                }
                refreshMirror(0, n);
            }
            unshotPower_.resize(n);
            for (uint32_t i = 0; i < n; ++i)
                unshotPower_[i] = rowPower(system_, i, rowOf(unshot_, i));
            break;
    }

    auto finish = [&](bool gathered) {
        if (!gathered) gatherFull();
        result.residual = relativeResidual(system_, b_, g_);
        result.converged = result.residual <= settings_.tolerance;
    };
    auto risky = [&]() {
        return risk.patches.empty()
            ? std::string()
            : concat("; patches that can amplify light: ", risk.description);
    };

    bool haveResidual = false;
    if (powerNorm(system_, system_.emission) == 0) {
        // No emission: B = 0 exactly.
        std::fill(b_.begin(), b_.end(), 0.0);
        std::fill(g_.begin(), g_.end(), 0.0);
        haveResidual = true;
        result.converged = true;
    }
    double previousChange = INFINITY;
    int growing = 0;
    bool extrapolated = false;  // B moved by extrapolate() after the last sweep
    for (int iteration = 1; !haveResidual && iteration <= settings_.maxIterations; ++iteration) {
        if (cancelRequested()) break;
        double change = 0;
        switch (settings_.kind) {
            case SolverKind::Jacobi:
                change = jacobiIteration();
                break;
            case SolverKind::GaussSeidel:
                change = gaussSeidelIteration();
                break;
            case SolverKind::Southwell:
                change = southwellIteration();
                break;
        }
        if (cancelled_) break;  // a partial sweep: its change is not an iteration's
        result.iterations = iteration;
        const double norm = powerNorm(system_, b_);
        if (!std::isfinite(change) || !std::isfinite(norm)) {
            return Error{concat("the ", solverKindName(settings_.kind),
                                " solve diverged (radiosity not finite after ", iteration,
                                " iterations)", risky())};
        }
        const double relative = norm > 0 ? change / norm : 0;
        result.changeHistory.push_back(relative);
        if (settings_.onIteration) settings_.onIteration(iteration, b_);
        growing = change > previousChange ? growing + 1 : 0;
        previousChange = change;
        if (growing >= kDivergenceIterations && relative > settings_.tolerance) {
            return Error{concat("the ", solverKindName(settings_.kind),
                                " solve diverges: the change per iteration grew for ", growing,
                                " iterations in a row (now ", formatNumber(relative, 3), ")",
                                risky())};
        }
        // The residual of the new iterate is about the change times the per-iteration
        // contraction (exactly so for Jacobi, whose change is the last iterate's residual):
        // only then is the true residual worth its gather.
        // (Not across an extrapolation, which moved B between the two changes.)
        const double ratio = result.changeHistory.size() > 1 && !extrapolated
            ? std::min(1.0, relative / result.changeHistory.end()[-2])
            : 1.0;
        if (relative * ratio <= settings_.tolerance || iteration == settings_.maxIterations) {
            finish(false);
            haveResidual = true;
            if (result.converged) break;
            if (iteration < settings_.maxIterations) haveResidual = false;
        }
        extrapolated = !delta_.empty() && iteration < settings_.maxIterations && extrapolate();
    }
    if (cancelled_) {
        // Stop at once: no final gather. The residual reported is the last change estimate.
        result.cancelled = true;
        result.residual = result.changeHistory.empty() ? 1.0 : result.changeHistory.back();
        result.warning = concat("cancelled after ", result.iterations, " iterations");
    } else if (!haveResidual) {
        finish(false);
    }
    if (!result.converged && !result.cancelled) {
        result.warning = concat("not converged after ", result.iterations, " iterations: residual ",
                                formatNumber(result.residual, 3), " > tolerance ",
                                formatNumber(settings_.tolerance, 3), risky());
    }
    result.radiosity = std::move(b_);
    result.gathered = std::move(g_);
    result.seconds = secondsSince(start);
    return result;
}

}  // namespace

bool parseSolverKind(const std::string& name, SolverKind& kind) {
    if (name == "gauss-seidel")
        kind = SolverKind::GaussSeidel;
    else if (name == "jacobi")
        kind = SolverKind::Jacobi;
    else if (name == "southwell")
        kind = SolverKind::Southwell;
    else
        return false;
    return true;
}

const char* solverKindName(SolverKind kind) {
    switch (kind) {
        case SolverKind::GaussSeidel:
            return "gauss-seidel";
        case SolverKind::Jacobi:
            return "jacobi";
        case SolverKind::Southwell:
            return "southwell";
    }
    return "?";
}

std::vector<std::string> solverKindNames() {
    return {solverKindName(SolverKind::GaussSeidel), solverKindName(SolverKind::Jacobi),
            solverKindName(SolverKind::Southwell)};
}

ConvergenceRisk findConvergenceRisk(const SparseMatrix& formFactors,
                                    const RadiositySystem& system) {
    return riskFromRowSums(system, parallelRowSums(formFactors));
}

void gatherAll(const SparseMatrix& formFactors, std::span<const double> radiosity,
               std::size_t wavelengthCount, std::span<double> gathered, int threads) {
    if (threads > 0) {
        tbb::task_arena arena(threads);
        arena.execute([&] { gatherAll(formFactors, radiosity, wavelengthCount, gathered, 0); });
        return;
    }
    const std::size_t m = wavelengthCount;
    const AccumulateFn<double> accumulate = accumulateFor<double>(m);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, formFactors.size, kRowGrain),
                      [&](const tbb::blocked_range<uint32_t>& range) {
                          for (uint32_t i = range.begin(); i != range.end(); ++i) {
                              double* g = gathered.data() + std::size_t(i) * m;
                              std::fill(g, g + m, 0.0);
                              accumulate(formFactors.columns.data(), formFactors.values.data(),
                                         formFactors.rowOffsets[i], formFactors.rowOffsets[i + 1],
                                         radiosity.data(), m, g);
                          }
                      });
}

double relativeResidual(const RadiositySystem& system, std::span<const double> radiosity,
                        std::span<const double> gathered) {
    const std::size_t m = system.wavelengthCount;
    std::vector<double> row(m);
    double residual = 0, norm = 0;
    for (uint32_t i = 0; i < system.patchCount; ++i) {
        applyOperator(system.operators[system.patchOperator[i]],
                      gathered.data() + std::size_t(i) * m, row.data(), system.emissionRow(i));
        residual += rowPowerOfDifference(system, i, row.data(), radiosity.data() + i * m);
        norm += rowPower(system, i, radiosity.data() + i * m);
    }
    return norm > 0 ? residual / norm : 0;
}

double powerNorm(const RadiositySystem& system, std::span<const double> values) {
    double norm = 0;
    for (uint32_t i = 0; i < system.patchCount; ++i)
        norm += rowPower(system, i, values.data() + std::size_t(i) * system.wavelengthCount);
    return norm;
}

Expected<SolverResult> solveRadiosity(const SparseMatrix& formFactors,
                                      const RadiositySystem& system,
                                      const SolverSettings& settings) {
    const std::size_t n = system.patchCount;
    const std::size_t m = system.wavelengthCount;
    if (formFactors.size != n || system.emission.size() != n * m || system.areas.size() != n ||
        system.patchOperator.size() != n || system.binWidthsNm.size() != m) {
        return Error{concat("the view-factor matrix has ", formFactors.size,
                            " rows but the radiosity system has ", n, " patches")};
    }
    if (!(settings.tolerance > 0) || settings.maxIterations < 0) {
        return Error{concat("--tolerance must be > 0 and --max-iterations >= 0 (got ",
                            settings.tolerance, ", ", settings.maxIterations, ")")};
    }
    if ((!settings.initialRadiosity.empty() && settings.initialRadiosity.size() != n * m) ||
        (!settings.rowSums.empty() && settings.rowSums.size() != n) ||
        (settings.transposed && settings.transposed->size != n)) {
        return Error{
            concat("the warm start, row sums or transpose given to the solver do not "
                   "match its ",
                   n, " patches x ", m, " wavelengths")};
    }
    if (settings.farGather && settings.kind == SolverKind::Southwell) {
        return Error{
            "the southwell solver shoots along the matrix's columns; the hierarchical "
            "transport solves with gauss-seidel or jacobi"};
    }
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    try {
        return arena.execute([&] { return Solver(formFactors, system, settings).run(); });
    } catch (const std::bad_alloc&) {
        return Error{concat("out of memory for the solver's work arrays (", n, " patches x ", m,
                            " wavelengths)")};
    }
}

}  // namespace daisy
