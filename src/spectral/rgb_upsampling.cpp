#include "spectral/rgb_upsampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/check.h"
#include "spectral/rgb_table.h"
#include "spectral/rgb_upsampling_fit.h"

namespace daisy {
namespace {

double smoothstep(double x) {
    return x * x * (3 - 2 * x);
}

}  // namespace

double sigmoid(double x) {
    if (std::isinf(x)) return x > 0 ? 1 : 0;
    return 0.5 + x / (2 * std::sqrt(1 + x * x));
}

double SigmoidPolynomial::operator()(double nm) const {
    const double u =
        std::clamp((nm - kSigmoidFirstNm) / (kSigmoidLastNm - kSigmoidFirstNm), 0.0, 1.0);
    return sigmoid((c[0] * u + c[1]) * u + c[2]);
}

RgbToSpectrumTable::RgbToSpectrumTable(int resolution, std::vector<float> coefficients)
    : resolution_(resolution), coefficients_(std::move(coefficients)) {
    DAISY_CHECK_OP(resolution, >=, 2);
    const std::size_t res = std::size_t(resolution);
    DAISY_CHECK_OP(coefficients_.size(), ==, 9 * res * res * res);
    zNodes_.resize(res);
    for (int k = 0; k < resolution; ++k)
        zNodes_[k] = zNode(k, resolution);
}

double RgbToSpectrumTable::zNode(int k, int resolution) {
    return smoothstep(smoothstep(double(k) / double(resolution - 1)));
}

std::array<double, 3> RgbToSpectrumTable::node(int largest, int zi, int yi, int xi) const {
    const std::size_t res = std::size_t(resolution_);
    const std::size_t index = (((std::size_t(largest) * res + zi) * res + yi) * res + xi) * 3;
    return {coefficients_[index], coefficients_[index + 1], coefficients_[index + 2]};
}

SigmoidPolynomial RgbToSpectrumTable::lookup(const Rgb& input) const {
    Rgb rgb;
    for (int c = 0; c < 3; ++c)
        rgb[c] = std::clamp(std::isfinite(input[c]) ? input[c] : 0.0, 0.0, 1.0);
    if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {
        // A constant spectrum v: S(x) = v at x = (v - 1/2) / sqrt(v (1 - v)); +-inf at 1 and 0.
        const double v = rgb[0];
        const double x = v <= 0 ? -std::numeric_limits<double>::infinity()
            : v >= 1            ? std::numeric_limits<double>::infinity()
                                : (v - 0.5) / std::sqrt(v * (1 - v));
        return SigmoidPolynomial{{0, 0, x}};
    }
    const int largest = rgb[0] > rgb[1] ? (rgb[0] > rgb[2] ? 0 : 2) : (rgb[1] > rgb[2] ? 1 : 2);
    const double z = rgb[largest];
    const int res = resolution_;
    const double x = rgb[(largest + 1) % 3] / z * (res - 1);
    const double y = rgb[(largest + 2) % 3] / z * (res - 1);
    const int xi = std::min(int(x), res - 2);
    const int yi = std::min(int(y), res - 2);
    // The last z node below z (z > 0 here since the colour is not grey).
    const int zi =
        int(std::upper_bound(zNodes_.begin(), zNodes_.end() - 1, z) - zNodes_.begin()) - 1;
    const int z0 = std::clamp(zi, 0, res - 2);
    const double dx = x - xi, dy = y - yi;
    const double dz = (z - zNodes_[z0]) / (zNodes_[z0 + 1] - zNodes_[z0]);
    SigmoidPolynomial result;
    for (int corner = 0; corner < 8; ++corner) {
        const int ox = corner & 1, oy = (corner >> 1) & 1, oz = (corner >> 2) & 1;
        const double weight = (ox ? dx : 1 - dx) * (oy ? dy : 1 - dy) * (oz ? dz : 1 - dz);
        if (weight == 0) continue;
        const std::array<double, 3> c = node(largest, z0 + oz, yi + oy, xi + ox);
        for (int j = 0; j < 3; ++j)
            result.c[j] += weight * c[j];
    }
    return result;
}

const RgbToSpectrumTable& srgbToSpectrumTable() {
    static const RgbToSpectrumTable kTable(
        kSrgbTableResolution,
        std::vector<float>(kSrgbTableCoefficients.begin(), kSrgbTableCoefficients.end()));
    return kTable;
}

SigmoidPolynomial rgbToReflectance(const Rgb& rgb) {
    return rgbToReflectance(rgb, srgbToSpectrumTable());
}

SigmoidPolynomial rgbToReflectance(const Rgb& rgb, const RgbToSpectrumTable& table) {
    const SigmoidPolynomial start = table.lookup(rgb);
    if (start.c[0] == 0 && start.c[1] == 0) return start;  // a grey: exact in closed form
    static const SigmoidFitter kFitter;
    Rgb clamped;
    for (int c = 0; c < 3; ++c)
        clamped[c] = std::clamp(std::isfinite(rgb[c]) ? rgb[c] : 0.0, 0.0, 1.0);
    return SigmoidPolynomial{kFitter.fit(clamped, start.c).coefficients};
}

RgbEmission rgbToEmission(const Rgb& rgb) {
    double m = 0;
    for (double v : rgb)
        m = std::max(m, std::isfinite(v) ? v : 0.0);
    if (m <= 0) return RgbEmission{SigmoidPolynomial{}, 0};
    const double scale = 2 * m;
    return RgbEmission{rgbToReflectance({rgb[0] / scale, rgb[1] / scale, rgb[2] / scale}), scale};
}

}  // namespace daisy
