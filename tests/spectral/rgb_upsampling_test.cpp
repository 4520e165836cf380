#include "spectral/rgb_upsampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "spectral/colorchecker.h"
#include "spectral/rgb_upsampling_fit.h"
#include "spectral/round_trip.h"

namespace daisy {
namespace {

// The oracle: RGB -> spectrum -> XYZ -> RGB on the fine set returns the colour within
// 2e-3 (linear sRGB, max abs) for 10,000 random in-gamut colours, and the spectra stay in [0, 1].
TEST(RgbUpsampling, RoundTripOnFineSet) {
    const ReflectanceRoundTrip roundTrip(fineWavelengths());
    SplitMix64 random(2019);
    double maxError = 0;
    for (int n = 0; n < 10000; ++n) {
        const Rgb rgb = {random.uniform(), random.uniform(), random.uniform()};
        const std::vector<double> samples = roundTrip.samples(rgb);
        for (double s : samples) {
            ASSERT_GE(s, 0);
            ASSERT_LE(s, 1);
        }
        const Rgb back = xyzToLinearSrgb(roundTrip.xyz(rgb));
        for (int c = 0; c < 3; ++c)
            maxError = std::max(maxError, std::abs(back[c] - rgb[c]));
    }
    EXPECT_LE(maxError, 2e-3);
    std::cout << "max round-trip error on the fine set: " << maxError << "\n";
}

TEST(RgbUpsampling, SpectraAreGreyForGreys) {
    // r = g = b = v is the constant spectrum v (closed form), exact for 0 and 1.
    for (double v : {0.0, 0.001, 0.18, 0.5, 0.9, 1.0}) {
        const SigmoidPolynomial s = rgbToReflectance({v, v, v});
        for (double nm : {360.0, 500.0, 700.0, 830.0})
            EXPECT_NEAR(s(nm), v, 1e-12) << v;
    }
}

TEST(RgbUpsampling, Sigmoid) {
    // Jakob & Hanika 2019: S(x) = 1/2 + x / (2 sqrt(1 + x^2)).
    EXPECT_DOUBLE_EQ(sigmoid(0), 0.5);
    EXPECT_DOUBLE_EQ(sigmoid(-INFINITY), 0);
    EXPECT_DOUBLE_EQ(sigmoid(INFINITY), 1);
    EXPECT_NEAR(sigmoid(1), 0.5 + 1 / (2 * std::sqrt(2.0)), 1e-15);
    EXPECT_NEAR(sigmoid(-3) + sigmoid(3), 1, 1e-15);
}

TEST(RgbUpsampling, CommittedTableAloneIsClose) {
    // The table's trilinear lookup without the polish: docs/spectral.md measures max 1.1e-2,
    // median 7e-4 in linear sRGB at resolution 33 (1 nm colorimetry, SigmoidFitter).
    const SigmoidFitter fitter;
    SplitMix64 random(7);
    double maxError = 0;
    for (int n = 0; n < 2000; ++n) {
        const Rgb rgb = {random.uniform(), random.uniform(), random.uniform()};
        const Rgb back = xyzToLinearSrgb(fitter.reflectanceXyz(srgbToSpectrumTable().lookup(rgb)));
        for (int c = 0; c < 3; ++c)
            maxError = std::max(maxError, std::abs(back[c] - rgb[c]));
    }
    EXPECT_LT(maxError, 1.5e-2);
    EXPECT_EQ(srgbToSpectrumTable().resolution(), 33);
}

TEST(RgbUpsampling, OptimiserAtSmallResolutionAgreesWithCommittedTable) {
    // Resolution 9 shares every node with the committed 33 (8 divides 32): node k of 9 is
    // node 4k of 33, in z (smoothstep^2 of k / 8 = 4k / 32) as in x and y.
    RgbTableFitStats stats;
    const RgbToSpectrumTable small = fitRgbToSpectrumTable(9, &stats);
    EXPECT_EQ(stats.fittedNodes + stats.closedFormNodes, 3u * 9 * 9 * 9);
    EXPECT_LE(stats.maxResidualLab, 1e-6);
    EXPECT_EQ(stats.nodesAboveTolerance, 0u);

    const RgbToSpectrumTable& committed = srgbToSpectrumTable();
    ASSERT_EQ(committed.resolution(), 33);
    double maxDifference = 0;
    for (int l = 0; l < 3; ++l) {
        for (int z = 0; z < 9; ++z) {
            EXPECT_DOUBLE_EQ(RgbToSpectrumTable::zNode(z, 9), RgbToSpectrumTable::zNode(4 * z, 33));
            for (int y = 0; y < 9; ++y) {
                for (int x = 0; x < 9; ++x) {
                    // The same colour: compare the spectra (the fit's solution is unique).
                    const SigmoidPolynomial a{small.node(l, z, y, x)};
                    const SigmoidPolynomial b{committed.node(l, 4 * z, 4 * y, 4 * x)};
                    for (double nm = 360; nm <= 830; nm += 5)
                        maxDifference = std::max(maxDifference, std::abs(a(nm) - b(nm)));
                }
            }
        }
    }
    // The fits agree to 3e-6; the committed table is rounded to 6 significant digits, which
    // moves its spectra by up to 2.8e-4 (coefficients near 100 carry 5e-4 absolute rounding).
    EXPECT_LT(maxDifference, 1e-3);

    // Its lookup is coarse; the polish from it is as good as from the committed table.
    const ReflectanceRoundTrip roundTrip(fineWavelengths(), small);
    SplitMix64 random(9);
    double maxError = 0;
    for (int n = 0; n < 300; ++n) {
        const Rgb rgb = {random.uniform(), random.uniform(), random.uniform()};
        const Rgb back = roundTrip(rgb);
        for (int c = 0; c < 3; ++c)
            maxError = std::max(maxError, std::abs(back[c] - rgb[c]));
    }
    EXPECT_LE(maxError, 2e-3);
}

TEST(RgbUpsampling, FitterHitsTargets) {
    const SigmoidFitter fitter;
    for (Rgb rgb : {Rgb{0.8, 0.1, 0.1}, Rgb{0.05, 0.9, 0.2}, Rgb{0.01, 0.02, 0.95}, Rgb{1, 1, 0},
                    Rgb{0.3, 0.3, 0.31}}) {
        const SigmoidFitter::Result result = fitter.fit(rgb, {0, 0, 0});
        EXPECT_LE(result.residualLab, kFitToleranceLab);
        const Xyz target = fitter.targetXyz(rgb);
        const Xyz got = fitter.reflectanceXyz(SigmoidPolynomial{result.coefficients});
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], target[c], 1e-6);
    }
    // The fit's white is CIE D65's, x = 0.31273, y = 0.32902 (CIE 015:2018 table T.3).
    const auto xy = xyzToXy(fitter.whiteXyz());
    EXPECT_NEAR(xy[0], 0.31273, 1e-5);
    EXPECT_NEAR(xy[1], 0.32902, 1e-5);
}

TEST(RgbUpsampling, Emission) {
    const RgbEmission e = rgbToEmission({2, 1, 0.5});
    EXPECT_DOUBLE_EQ(e.scale, 4);  // 2 max: the shape is the reflectance of rgb / 4
    EXPECT_EQ(rgbToEmission({0, 0, 0}).scale, 0);
    EXPECT_EQ(rgbToEmission({-1, 0, 0}).scale, 0);
}

}  // namespace
}  // namespace daisy
