#include "spectral/color.h"

#include <gtest/gtest.h>

#include <cmath>

namespace daisy {
namespace {

// IEC 61966-2-1:1999 section 5.2 prints both matrices rounded to 4 decimals.
constexpr Matrix3 kIecRgbToXyz = {
    {{0.4124, 0.3576, 0.1805}, {0.2126, 0.7152, 0.0722}, {0.0193, 0.1192, 0.9505}}};
constexpr Matrix3 kIecXyzToRgb = {
    {{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}}};

TEST(SpectralColor, SrgbMatricesMatchIec61966) {
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(linearSrgbToXyzMatrix()[r][c], kIecRgbToXyz[r][c], 5e-5) << r << c;
            // The printed inverse is rounded from a rounded forward matrix: 5e-4.
            EXPECT_NEAR(xyzToLinearSrgbMatrix()[r][c], kIecXyzToRgb[r][c], 5e-4) << r << c;
        }
    }
}

TEST(SpectralColor, WhiteMapsToD65) {
    // RGB (1, 1, 1) is the D65 white point x = 0.3127, y = 0.3290 with Y = 1 (IEC 61966-2-1).
    const Xyz white = linearSrgbToXyz({1, 1, 1});
    EXPECT_NEAR(white[1], 1.0, 1e-12);
    const auto xy = xyzToXy(white);
    EXPECT_NEAR(xy[0], 0.3127, 1e-12);
    EXPECT_NEAR(xy[1], 0.3290, 1e-12);
    const Rgb back = xyzToLinearSrgb(white);
    for (double v : back)
        EXPECT_NEAR(v, 1.0, 1e-12);
}

TEST(SpectralColor, TransferCurve) {
    // IEC 61966-2-1 equations: the linear segment below 0.0031308, 1.055 v^(1/2.4) - 0.055 above.
    EXPECT_DOUBLE_EQ(srgbEncode(0), 0);
    EXPECT_DOUBLE_EQ(srgbEncode(1), 1);
    EXPECT_NEAR(srgbEncode(0.002), 12.92 * 0.002, 1e-15);
    EXPECT_NEAR(srgbEncode(0.18), 0.461356, 1e-6);  // 18% grey encodes to ~118/255
    EXPECT_NEAR(srgbDecode(0.5), 0.214041, 1e-6);
    for (double v = 0; v <= 1; v += 0.01)
        EXPECT_NEAR(srgbDecode(srgbEncode(v)), v, 1e-12);
    EXPECT_EQ(srgbEncode(-1), 0);
    EXPECT_DOUBLE_EQ(srgbEncode(2), 1);
}

TEST(SpectralColor, LabOfWhiteAndGrey) {
    const Xyz white = linearSrgbToXyz({1, 1, 1});
    const Lab lab = xyzToLab(white, white);
    EXPECT_NEAR(lab[0], 100, 1e-9);
    EXPECT_NEAR(lab[1], 0, 1e-9);
    EXPECT_NEAR(lab[2], 0, 1e-9);
    // CIE 015:2018: L* = 116 (Y/Yn)^(1/3) - 16, so Y = 0.18 gives L* = 49.496.
    const Lab grey = xyzToLab({white[0] * 0.18, 0.18, white[2] * 0.18}, white);
    EXPECT_NEAR(grey[0], 49.4961, 1e-4);
    // Below (6/29)^3 the linear branch: L* = 903.3 Y.
    EXPECT_NEAR(xyzToLab({0, 0.001, 0}, white)[0], 24389.0 / 27.0 * 0.001, 1e-9);
    EXPECT_DOUBLE_EQ(deltaE76({50, 3, 4}, {50, 0, 0}), 5);
}

TEST(SpectralColor, BradfordMapsWhiteToWhite) {
    const Xyz d65 = xyToXyz({0.3127, 0.3290});
    const Xyz a = xyToXyz({0.44757, 0.40745});  // CIE illuminant A, CIE 015:2018 table 1
    const Xyz adapted = adaptXyzBradford(a, a, d65);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(adapted[c], d65[c], 1e-12);
    // Linear: half the white maps to half the white.
    const Xyz half = adaptXyzBradford({a[0] / 2, a[1] / 2, a[2] / 2}, a, d65);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(half[c], d65[c] / 2, 1e-12);
}

TEST(SpectralColor, MatrixInverse) {
    const Matrix3 product = multiply(linearSrgbToXyzMatrix(), xyzToLinearSrgbMatrix());
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(product[r][c], r == c ? 1 : 0, 1e-14);
    }
}

// Sharma, Wu & Dalal 2005, Table 1 (supplementary CIEDE2000 test data): pairs 1, 4, 7, 9-17, 19,
// 25, 31 and 34 (L1, a1, b1, L2, a2, b2, Delta E00 as printed to 4 decimals). Pairs 9-16 sit on
// the hue-angle discontinuities the paper warns about (eqs. 10 and 14).
TEST(SpectralColor, DeltaE2000MatchesSharmaWuDalalTable1) {
    struct Pair {
        Lab a, b;
        double deltaE;
    };
    const Pair pairs[] = {
        {{50.0000, 2.6772, -79.7751}, {50.0000, 0.0000, -82.7485}, 2.0425},
        {{50.0000, -1.3802, -84.2814}, {50.0000, 0.0000, -82.7485}, 1.0000},
        {{50.0000, 0.0000, 0.0000}, {50.0000, -1.0000, 2.0000}, 2.3669},
        {{50.0000, 2.4900, -0.0010}, {50.0000, -2.4900, 0.0009}, 7.1792},
        {{50.0000, 2.4900, -0.0010}, {50.0000, -2.4900, 0.0010}, 7.1792},
        {{50.0000, 2.4900, -0.0010}, {50.0000, -2.4900, 0.0011}, 7.2195},
        {{50.0000, 2.4900, -0.0010}, {50.0000, -2.4900, 0.0012}, 7.2195},
        {{50.0000, -0.0010, 2.4900}, {50.0000, 0.0009, -2.4900}, 4.8045},
        {{50.0000, -0.0010, 2.4900}, {50.0000, 0.0010, -2.4900}, 4.8045},
        {{50.0000, -0.0010, 2.4900}, {50.0000, 0.0011, -2.4900}, 4.7461},
        {{50.0000, 2.5000, 0.0000}, {50.0000, 0.0000, -2.5000}, 4.3065},
        {{50.0000, 2.5000, 0.0000}, {73.0000, 25.0000, -18.0000}, 27.1492},
        {{50.0000, 2.5000, 0.0000}, {56.0000, -27.0000, -3.0000}, 31.9030},
        {{60.2574, -34.0099, 36.2677}, {60.4626, -34.1751, 39.4387}, 1.2644},
        {{90.8027, -2.0831, 1.4410}, {91.1528, -1.6435, 0.0447}, 1.4441},
        {{2.0776, 0.0795, -1.1350}, {0.9033, -0.0636, -0.5514}, 0.9082},
    };
    for (const Pair& pair : pairs) {
        EXPECT_NEAR(deltaE2000(pair.a, pair.b), pair.deltaE, 5e-5) << pair.a[1] << " " << pair.b[1];
        EXPECT_NEAR(deltaE2000(pair.b, pair.a), pair.deltaE, 5e-5);
    }
    EXPECT_EQ(deltaE2000({40, 30, -20}, {40, 30, -20}), 0);
}

TEST(SpectralColor, Srgb8ToLabOfWhiteBlackAndGrey) {
    const Lab white = srgb8ToLab({255, 255, 255});
    EXPECT_NEAR(white[0], 100, 1e-9);
    EXPECT_NEAR(white[1], 0, 1e-9);
    EXPECT_NEAR(white[2], 0, 1e-9);
    EXPECT_NEAR(srgb8ToLab({0, 0, 0})[0], 0, 1e-12);
    // 119/255 decodes to linear 0.18447 (IEC 61966-2-1 curve), L* = 116 Y^(1/3) - 16 = 50.03.
    const double y = std::pow((119 / 255.0 + 0.055) / 1.055, 2.4);
    EXPECT_NEAR(srgb8ToLab({119, 119, 119})[0], 116 * std::cbrt(y) - 16, 1e-9);
}

}  // namespace
}  // namespace daisy
