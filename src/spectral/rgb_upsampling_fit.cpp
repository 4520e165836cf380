#include "spectral/rgb_upsampling_fit.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/check.h"
#include "core/timer.h"
#include "spectral/cie_tables.h"

namespace daisy {
namespace {

constexpr int kMaxIterations = 50;
constexpr int kMaxHalvings = 30;
// Table nodes for black and white are stored as constant spectra this far from 0 and 1.
constexpr double kGreyMargin = 1e-4;

// d f / d t of the CIELAB companding function f (CIE 015:2018 section 8.2.1).
double labFDerivative(double t) {
    constexpr double kDelta = 6.0 / 29.0;
    if (t > kDelta * kDelta * kDelta) return 1.0 / (3 * std::cbrt(t * t));
    return 1.0 / (3 * kDelta * kDelta);
}

// d Lab / d XYZ at `xyz`.
Matrix3 labJacobian(const Xyz& xyz, const Xyz& white) {
    const double fx = labFDerivative(xyz[0] / white[0]) / white[0];
    const double fy = labFDerivative(xyz[1] / white[1]) / white[1];
    const double fz = labFDerivative(xyz[2] / white[2]) / white[2];
    return {{{0, 116 * fy, 0}, {500 * fx, -500 * fy, 0}, {0, 200 * fy, -200 * fz}}};
}

// Solves a x = b by Cramer's rule; false when a is (numerically) singular.
bool solve3(const Matrix3& a, const std::array<double, 3>& b, std::array<double, 3>& x) {
    const auto det = [](const Matrix3& m) {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
            m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
            m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    const double d = det(a);
    double scale = 0;
    for (const auto& row : a) {
        for (double v : row)
            scale = std::max(scale, std::abs(v));
    }
    if (!std::isfinite(d) || std::abs(d) <= 1e-30 * scale * scale * scale) return false;
    for (int c = 0; c < 3; ++c) {
        Matrix3 m = a;
        for (int r = 0; r < 3; ++r)
            m[r][c] = b[r];
        x[c] = det(m) / d;
    }
    return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

double norm(const std::array<double, 3>& v) {
    return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

}  // namespace

SigmoidFitter::SigmoidFitter() {
    const CieIlluminantTable* d65 = findCieIlluminant("D65");
    DAISY_CHECK(d65 != nullptr);
    weights_.resize(kCieCmfCount);
    u_.resize(kCieCmfCount);
    double whiteY = 0;
    for (int i = 0; i < kCieCmfCount; ++i) {
        const double nm = kCieCmfFirstNm + i;
        const double power = evaluateCieIlluminant(*d65, nm);
        for (int c = 0; c < 3; ++c)
            weights_[i][c] = power * kCie1931Cmf[i][c];
        whiteY += weights_[i][1];
        u_[i] = (nm - kSigmoidFirstNm) / (kSigmoidLastNm - kSigmoidFirstNm);
    }
    white_ = {0, 0, 0};
    for (auto& w : weights_) {
        for (int c = 0; c < 3; ++c) {
            w[c] /= whiteY;
            white_[c] += w[c];
        }
    }
    targetMatrix_ = srgbPrimariesToXyzMatrix(white_);
}

Xyz SigmoidFitter::evaluate(const std::array<double, 3>& c, Matrix3* jacobian) const {
    Xyz xyz{0, 0, 0};
    if (jacobian) *jacobian = Matrix3{};
    for (std::size_t i = 0; i < weights_.size(); ++i) {
        const double u = u_[i];
        const double x = (c[0] * u + c[1]) * u + c[2];
        const double s = sigmoid(x);
        for (int r = 0; r < 3; ++r)
            xyz[r] += weights_[i][r] * s;
        if (jacobian) {
            // S'(x) = 1 / (2 (1 + x^2)^(3/2)); dx/dc = (u^2, u, 1).
            const double slope = 0.5 / std::pow(1 + x * x, 1.5);
            const std::array<double, 3> dx = {u * u, u, 1};
            for (int r = 0; r < 3; ++r) {
                for (int j = 0; j < 3; ++j)
                    (*jacobian)[r][j] += weights_[i][r] * slope * dx[j];
            }
        }
    }
    return xyz;
}

Xyz SigmoidFitter::targetXyz(const Rgb& rgb) const {
    return multiply(targetMatrix_, rgb);
}

Xyz SigmoidFitter::reflectanceXyz(const SigmoidPolynomial& shape) const {
    return evaluate(shape.c, nullptr);
}

SigmoidFitter::Result SigmoidFitter::fit(const Rgb& target,
                                         const std::array<double, 3>& start) const {
    const Lab goal = xyzToLab(targetXyz(target), white_);
    const auto residualOf = [&](const Xyz& xyz) {
        const Lab lab = xyzToLab(xyz, white_);
        return std::array<double, 3>{lab[0] - goal[0], lab[1] - goal[1], lab[2] - goal[2]};
    };
    Result result;
    result.coefficients = start;
    Matrix3 jacobian;
    std::array<double, 3> residual = residualOf(evaluate(result.coefficients, &jacobian));
    double residualNorm = norm(residual);
    for (; result.iterations < kMaxIterations && residualNorm > kFitToleranceLab;
         ++result.iterations) {
        const Xyz xyz = evaluate(result.coefficients, &jacobian);
        const Matrix3 j = multiply(labJacobian(xyz, white_), jacobian);
        std::array<double, 3> step;
        if (!solve3(j, {-residual[0], -residual[1], -residual[2]}, step)) break;
        // Gauss-Newton step, halved until the residual decreases.
        bool improved = false;
        double fraction = 1;
        for (int h = 0; h < kMaxHalvings && !improved; ++h, fraction *= 0.5) {
            std::array<double, 3> trial;
            for (int k = 0; k < 3; ++k)
                trial[k] = result.coefficients[k] + fraction * step[k];
            const std::array<double, 3> trialResidual = residualOf(evaluate(trial, nullptr));
            const double trialNorm = norm(trialResidual);
            if (trialNorm < residualNorm) {
                result.coefficients = trial;
                residual = trialResidual;
                residualNorm = trialNorm;
                improved = true;
            }
        }
        if (!improved) break;
    }
    result.residualLab = residualNorm;
    return result;
}

RgbToSpectrumTable fitRgbToSpectrumTable(int resolution, RgbTableFitStats* stats) {
    DAISY_CHECK_OP(resolution, >=, 2);
    const auto started = Clock::now();
    const std::size_t res = std::size_t(resolution);
    const SigmoidFitter fitter;
    std::vector<float> coefficients(9 * res * res * res);
    std::vector<double> residuals(3 * res * res * res);
    const int startZ = resolution / 5;

    // One task per (largest component l, y node j): x nodes in order, then z from startZ.
    tbb::parallel_for(tbb::blocked_range<int>(0, 3 * resolution), [&](const auto& range) {
        for (int row = range.begin(); row < range.end(); ++row) {
            const int l = row / resolution, yi = row % resolution;
            const double y = double(yi) / double(resolution - 1);
            std::array<double, 3> columnStart{0, 0, 0};
            for (int xi = 0; xi < resolution; ++xi) {
                const double x = double(xi) / double(resolution - 1);
                const auto fitNode = [&](int zi, const std::array<double, 3>& from) {
                    const double z = RgbToSpectrumTable::zNode(zi, resolution);
                    Rgb rgb;
                    rgb[l] = z;
                    rgb[(l + 1) % 3] = x * z;
                    rgb[(l + 2) % 3] = y * z;
                    SigmoidFitter::Result fitted;
                    const bool closedForm =
                        zi == 0 || (xi == resolution - 1 && yi == resolution - 1);
                    if (closedForm) {
                        // Black and greys: a constant spectrum (closed form), kept kGreyMargin away
                        // from 0 and 1, where the coefficients would be infinite.
                        const double v = std::clamp(z, kGreyMargin, 1 - kGreyMargin);
                        fitted.coefficients = {0, 0, (v - 0.5) / std::sqrt(v * (1 - v))};
                        fitted.residualLab = deltaE76(
                            xyzToLab(fitter.reflectanceXyz(SigmoidPolynomial{fitted.coefficients}),
                                     fitter.whiteXyz()),
                            xyzToLab(fitter.targetXyz(rgb), fitter.whiteXyz()));
                    } else {
                        fitted = fitter.fit(rgb, from);
                        if (fitted.residualLab > kFitToleranceLab &&
                            from != std::array<double, 3>{}) {
                            const SigmoidFitter::Result fresh = fitter.fit(rgb, {0, 0, 0});
                            if (fresh.residualLab < fitted.residualLab) fitted = fresh;
                        }
                    }
                    const std::size_t node = ((std::size_t(l) * res + zi) * res + yi) * res + xi;
                    for (int k = 0; k < 3; ++k)
                        coefficients[node * 3 + k] = float(fitted.coefficients[k]);
                    residuals[node] = closedForm ? -1 : fitted.residualLab;
                    return fitted.coefficients;
                };
                const std::array<double, 3> atStart = fitNode(startZ, columnStart);
                columnStart = atStart;
                std::array<double, 3> previous = atStart;
                for (int zi = startZ + 1; zi < resolution; ++zi)
                    previous = fitNode(zi, previous);
                previous = atStart;
                for (int zi = startZ - 1; zi >= 0; --zi)
                    previous = fitNode(zi, previous);
            }
        }
    });

    if (stats) {
        *stats = RgbTableFitStats{};
        double sum = 0;
        for (double r : residuals) {
            if (r < 0) {
                ++stats->closedFormNodes;
                continue;
            }
            ++stats->fittedNodes;
            stats->maxResidualLab = std::max(stats->maxResidualLab, r);
            sum += r;
            if (r > kFitToleranceLab) ++stats->nodesAboveTolerance;
        }
        stats->meanResidualLab = stats->fittedNodes ? sum / double(stats->fittedNodes) : 0;
        stats->seconds = secondsSince(started);
    }
    return RgbToSpectrumTable(resolution, std::move(coefficients));
}

}  // namespace daisy
