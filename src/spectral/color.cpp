#include "spectral/color.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace daisy {
namespace {

// Bradford cone response matrix (Lam 1985), as used by CIECAM97s.
constexpr Matrix3 kBradford = {
    {{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};

double labF(double t) {
    constexpr double kDelta = 6.0 / 29.0;
    return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3 * kDelta * kDelta) + 4.0 / 29.0;
}

}  // namespace

Matrix3 multiply(const Matrix3& a, const Matrix3& b) {
    Matrix3 out{};
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            for (int k = 0; k < 3; ++k)
                out[r][c] += a[r][k] * b[k][c];
        }
    }
    return out;
}

std::array<double, 3> multiply(const Matrix3& m, const std::array<double, 3>& v) {
    return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
            m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

Matrix3 inverse(const Matrix3& m) {
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
        m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
        m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    DAISY_CHECK(std::abs(det) > 1e-300);
    Matrix3 out;
    out[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / det;
    out[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det;
    out[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det;
    out[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) / det;
    out[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det;
    out[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det;
    out[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) / det;
    out[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det;
    out[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det;
    return out;
}

// Columns are the primaries' XYZ scaled so that RGB (1, 1, 1) maps to the white: the standard
// derivation (SMPTE RP 177-1993 section 3.3).
Matrix3 srgbPrimariesToXyzMatrix(const Xyz& whiteXyz) {
    const std::array<std::array<double, 2>, 3> primaries = {kSrgbRedXy, kSrgbGreenXy, kSrgbBlueXy};
    Matrix3 p{};
    for (int c = 0; c < 3; ++c) {
        const Xyz column = xyToXyz(primaries[c]);
        for (int r = 0; r < 3; ++r)
            p[r][c] = column[r];
    }
    const std::array<double, 3> scale = multiply(inverse(p), whiteXyz);
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c)
            p[r][c] *= scale[c];
    }
    return p;
}

const Matrix3& linearSrgbToXyzMatrix() {
    static const Matrix3 kMatrix = srgbPrimariesToXyzMatrix(xyToXyz(kD65WhiteXy));
    return kMatrix;
}

const Matrix3& xyzToLinearSrgbMatrix() {
    static const Matrix3 kMatrix = inverse(linearSrgbToXyzMatrix());
    return kMatrix;
}

Rgb xyzToLinearSrgb(const Xyz& xyz) {
    return multiply(xyzToLinearSrgbMatrix(), xyz);
}

Xyz linearSrgbToXyz(const Rgb& rgb) {
    return multiply(linearSrgbToXyzMatrix(), rgb);
}

double srgbEncode(double linear) {
    const double v = std::clamp(linear, 0.0, 1.0);
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

double srgbDecode(double encoded) {
    const double v = std::clamp(encoded, 0.0, 1.0);
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

std::array<double, 2> xyzToXy(const Xyz& xyz) {
    const double sum = xyz[0] + xyz[1] + xyz[2];
    if (sum == 0) return {0, 0};
    return {xyz[0] / sum, xyz[1] / sum};
}

Xyz xyToXyz(const std::array<double, 2>& xy, double luminanceY) {
    DAISY_CHECK(xy[1] > 0);
    return {xy[0] / xy[1] * luminanceY, luminanceY, (1 - xy[0] - xy[1]) / xy[1] * luminanceY};
}

Lab xyzToLab(const Xyz& xyz, const Xyz& whiteXyz) {
    const double fx = labF(xyz[0] / whiteXyz[0]);
    const double fy = labF(xyz[1] / whiteXyz[1]);
    const double fz = labF(xyz[2] / whiteXyz[2]);
    return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

double deltaE76(const Lab& a, const Lab& b) {
    return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

Xyz adaptXyzBradford(const Xyz& xyz, const Xyz& sourceWhite, const Xyz& targetWhite) {
    const std::array<double, 3> source = multiply(kBradford, sourceWhite);
    const std::array<double, 3> target = multiply(kBradford, targetWhite);
    std::array<double, 3> cone = multiply(kBradford, xyz);
    for (int c = 0; c < 3; ++c)
        cone[c] *= target[c] / source[c];
    return multiply(inverse(kBradford), cone);
}

}  // namespace daisy
