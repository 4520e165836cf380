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

double deltaE2000(const Lab& a, const Lab& b) {
    // Sharma, Wu & Dalal 2005, equations numbered as in the paper; angles in degrees.
    constexpr double kPi = 3.14159265358979323846;
    constexpr double kDegree = kPi / 180;
    constexpr double k25Pow7 = 6103515625.0;  // 25^7
    const double c1 = std::hypot(a[1], a[2]);  // eq. 2
    const double c2 = std::hypot(b[1], b[2]);
    const double cMean7 = std::pow((c1 + c2) / 2, 7);  // eq. 3
    const double g = 0.5 * (1 - std::sqrt(cMean7 / (cMean7 + k25Pow7)));  // eq. 4
    const double a1 = (1 + g) * a[1];  // eq. 5
    const double a2 = (1 + g) * b[1];
    const double c1p = std::hypot(a1, a[2]);  // eq. 6
    const double c2p = std::hypot(a2, b[2]);
    const auto hue = [&](double bValue, double aPrime) {  // eq. 7, in [0, 360)
        if (bValue == 0 && aPrime == 0) return 0.0;
        const double h = std::atan2(bValue, aPrime) / kDegree;
        return h < 0 ? h + 360 : h;
    };
    const double h1 = hue(a[2], a1);
    const double h2 = hue(b[2], a2);
    const double deltaL = b[0] - a[0];  // eq. 8
    const double deltaC = c2p - c1p;  // eq. 9
    const bool achromatic = c1p * c2p == 0;
    double deltaH = 0;  // eq. 10
    if (!achromatic) {
        deltaH = h2 - h1;
        if (deltaH > 180) deltaH -= 360;
        if (deltaH < -180) deltaH += 360;
    }
    const double deltaHBig = 2 * std::sqrt(c1p * c2p) * std::sin(deltaH * kDegree / 2);  // eq. 11
    const double lMean = (a[0] + b[0]) / 2;  // eq. 12
    const double cpMean = (c1p + c2p) / 2;  // eq. 13
    double hMean = h1 + h2;  // eq. 14
    if (!achromatic) {
        if (std::abs(h1 - h2) <= 180) {
            hMean = (h1 + h2) / 2;
        } else {
            hMean = h1 + h2 < 360 ? (h1 + h2 + 360) / 2 : (h1 + h2 - 360) / 2;
        }
    }
    const double t = 1 - 0.17 * std::cos((hMean - 30) * kDegree) +
        0.24 * std::cos(2 * hMean * kDegree) + 0.32 * std::cos((3 * hMean + 6) * kDegree) -
        0.20 * std::cos((4 * hMean - 63) * kDegree);  // eq. 15
    const double deltaTheta = 30 * std::exp(-std::pow((hMean - 275) / 25, 2));  // eq. 16
    const double cpMean7 = std::pow(cpMean, 7);
    const double rC = 2 * std::sqrt(cpMean7 / (cpMean7 + k25Pow7));  // eq. 17
    const double lOffset2 = (lMean - 50) * (lMean - 50);
    const double sL = 1 + 0.015 * lOffset2 / std::sqrt(20 + lOffset2);  // eq. 18
    const double sC = 1 + 0.045 * cpMean;  // eq. 19
    const double sH = 1 + 0.015 * cpMean * t;  // eq. 20
    const double rT = -std::sin(2 * deltaTheta * kDegree) * rC;  // eq. 21
    const double l = deltaL / sL;
    const double c = deltaC / sC;
    const double h = deltaHBig / sH;
    return std::sqrt(l * l + c * c + h * h + rT * c * h);  // eq. 22
}

Lab srgb8ToLab(const std::array<uint8_t, 3>& srgb8) {
    const Rgb linear{srgbDecode(srgb8[0] / 255.0), srgbDecode(srgb8[1] / 255.0),
                     srgbDecode(srgb8[2] / 255.0)};
    return xyzToLab(linearSrgbToXyz(linear), linearSrgbToXyz({1, 1, 1}));
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
