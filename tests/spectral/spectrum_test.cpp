#include "spectral/spectrum.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "spectral/cie_tables.h"

namespace daisy {
namespace {

// Spectral power on a set: sum_k s_k w_k.
double power(const WavelengthSet& set, const std::vector<double>& samples) {
    double sum = 0;
    for (std::size_t k = 0; k < set.size(); ++k)
        sum += samples[k] * set.binWidthNm(k);
    return sum;
}

TEST(SpectralSpectrum, SamplingConservesPowerOfNarrowLines) {
    // A Gaussian of FWHM f and peak 1 has integral f sqrt(pi / (4 ln 2)) (closed form); hat
    // sampling keeps it on any set, however coarse, as long as the line is inside the domain.
    const double fwhm = 4;
    const double integral = fwhm * std::sqrt(M_PI / (4 * std::log(2.0)));
    const Spectrum line = Spectrum::gaussians({{427.0, fwhm, 1.0}});
    for (const WavelengthSet& set :
         {daisyriotWavelengths(), meyer4Wavelengths(), visibleWavelengths(), fineWavelengths()}) {
        EXPECT_NEAR(power(set, sampleSpectrum(set, line, SpectrumRole::Emission)), integral,
                    1e-6 * integral)
            << set.name();
    }
}

TEST(SpectralSpectrum, PiecewiseLinearOnTheSamplesIsExact) {
    // The mean of a straight line under a symmetric hat is its value at the centre; at the
    // fine set's ends the hat is half a hat (weight 1 -> 0 over 5 nm), whose mean is 5/3 nm in.
    const WavelengthSet fine = fineWavelengths();
    const Spectrum ramp = Spectrum::tabulated({360, 830}, {0.1, 0.9}, true);
    const std::vector<double> samples = sampleSpectrum(fine, ramp, SpectrumRole::Emission);
    for (std::size_t k = 1; k + 1 < fine.size(); ++k)
        EXPECT_NEAR(samples[k], ramp(fine.wavelengthNm(k)), 1e-9);
    EXPECT_NEAR(samples.front(), ramp(360 + 5.0 / 3), 1e-9);
    EXPECT_NEAR(samples.back(), ramp(830 - 5.0 / 3), 1e-9);
    const Spectrum constant = Spectrum::constant(0.25);
    for (double v : sampleSpectrum(daisyriotWavelengths(), constant, SpectrumRole::Emission))
        EXPECT_NEAR(v, 0.25, 1e-12);
}

TEST(SpectralSpectrum, EmissionTableEndingAtTheSetsEndSamplesItsOwnMeanThere) {
    // The Cornell light's table, 400..700 nm, on the default 400:700:10 set, which ends at the
    // same wavelengths. The flat parts of the end hats (360..400, 700..830 nm) lie outside the
    // table and do not count (spectrum.h), so each end sample is the mean of the table's linear
    // interpolant under the half hat that the table covers. By hand: a line from s0 (at the far
    // end of the half hat, weight 0) to s1 (at the sample, weight 1) has hat-weighted mean
    // (s0 + 2 s1) / 3. At 700 nm, s(690) = 15.6 + 0.9 x 2.8 = 18.12 and s(700) = 18.4: 18.30667.
    // At 400 nm, s(400) = 0 and s(410) = 0.8: 0.26667. Inside, the hat mean of a line is its
    // value at the sample: 18.12 at 690 nm. (Diluted over the flat part, 700 nm was 0.678.)
    const WavelengthSet set = autoWavelengths();
    ASSERT_EQ(set.wavelengthNm(0), 400);
    ASSERT_EQ(set.wavelengthNm(set.size() - 1), 700);
    const SpectrumSpec cornell{TabulatedSpectrum{{400, 500, 600, 700}, {0, 8, 15.6, 18.4}}, 1.0};
    auto samples = sampleSpectrum(set, cornell, SpectrumRole::Emission);
    ASSERT_TRUE(samples);
    const std::size_t last = set.size() - 1;
    EXPECT_NEAR(samples->back(), (18.12 + 2 * 18.4) / 3, 1e-9);
    EXPECT_NEAR((*samples)[last - 1], 18.12, 1e-9);
    EXPECT_NEAR(samples->front(), (2 * 0.0 + 0.8) / 3, 1e-9);
    EXPECT_NEAR((*samples)[1], 0.8, 1e-9);
    // A constant table over 380..780 nm covers both end samples' half hats and part of their
    // flat parts: every sample is the constant (it was 2 x 85 / 135 at 700 nm before).
    auto flat = sampleSpectrum(set, SpectrumSpec{TabulatedSpectrum{{380, 780}, {2, 2}}, 1.0},
                               SpectrumRole::Emission);
    ASSERT_TRUE(flat);
    for (const double v : *flat)
        EXPECT_NEAR(v, 2, 1e-12);
    // A table over the whole domain still conserves power: sum_k s_k w_k = its integral over
    // 360..830 nm, (0.5 + 1.5) / 2 x 470 at a straight line from 0.5 to 1.5.
    auto wide = sampleSpectrum(set, SpectrumSpec{TabulatedSpectrum{{360, 830}, {0.5, 1.5}}, 1.0},
                               SpectrumRole::Emission);
    ASSERT_TRUE(wide);
    EXPECT_NEAR(power(set, *wide), 470, 1e-9);
}

TEST(SpectralSpectrum, ReflectanceIsPointSampled) {
    const Spectrum bump = Spectrum::tabulated({490, 500, 510}, {0, 1, 0}, true);
    const WavelengthSet set = daisyriotWavelengths();
    const std::vector<double> points = sampleSpectrum(set, bump, SpectrumRole::Reflectance);
    EXPECT_DOUBLE_EQ(points[3], 1);  // the value at 500 nm
    const std::vector<double> means = sampleSpectrum(set, bump, SpectrumRole::Emission);
    // integral of bump * hat = 2 * integral_0^10 (1 - d/10)(1 - d/50) dd = 28/3, over a 50 nm bin.
    EXPECT_NEAR(means[3], 28.0 / 3 / 50, 1e-9);
}

TEST(SpectralSpectrum, TableEnds) {
    const Spectrum held = Spectrum::tabulated({400, 500}, {0.2, 0.6}, true);
    EXPECT_DOUBLE_EQ(held(300), 0.2);
    EXPECT_DOUBLE_EQ(held(450), 0.4);
    EXPECT_DOUBLE_EQ(held(900), 0.6);
    const Spectrum zero = Spectrum::tabulated({400, 500}, {0.2, 0.6}, false);
    EXPECT_DOUBLE_EQ(zero(399), 0);
    EXPECT_DOUBLE_EQ(zero(501), 0);
    // The jump at the end is integrated one-sided: integral = 100 * mean(0.2, 0.6) exactly.
    EXPECT_NEAR(zero.integrate(300, 600), 40, 1e-9);
}

TEST(SpectralSpectrum, BlackbodyWienPeak) {
    // Wien's displacement law: peak at b / T, b = 2.897771955e-3 m K (CODATA 2018), the root of
    // x = 5 (1 - exp(-x)) for Planck's law per unit wavelength.
    for (double kelvin : {2700.0, 5778.0, 6500.0, 10000.0}) {
        const Spectrum planck = Spectrum::blackbody(kelvin);
        const double peak = 2.897771955e6 / kelvin;
        EXPECT_NEAR(wienPeakNm(kelvin), peak, 1e-9);
        EXPECT_NEAR(planck(peak), 1, 1e-12);  // normalised to 1 at the peak
        // Golden-section search for the maximum.
        double a = peak * 0.5, b = peak * 2;
        const double g = (std::sqrt(5.0) - 1) / 2;
        for (int i = 0; i < 200; ++i) {
            const double c = b - g * (b - a), d = a + g * (b - a);
            (planck(c) > planck(d) ? b : a) = planck(c) > planck(d) ? d : c;
        }
        EXPECT_NEAR((a + b) / 2, peak, 1e-3) << kelvin;
    }
}

TEST(SpectralSpectrum, PlanckRadiance) {
    // Planck's law from the SI defining constants h, c, k (exact since 2019) at 500 nm and
    // 5778 K: 2 h c^2 / l^5 / (exp(h c / (l k T)) - 1) = 26375.670 W sr^-1 m^-2 nm^-1.
    EXPECT_NEAR(planckRadianceNm(500, 5778), 26375.670, 1e-2);
}

TEST(SpectralSpectrum, IlluminantsAreLuminanceNormalised) {
    // Every CIE preset has Y = 1 (the luminance of a flat spectrum of value 1) on the fine set.
    const WavelengthSet fine = fineWavelengths();
    for (const char* name : {"D65", "D50", "A", "F1", "F7", "F11"}) {
        auto s = illuminantPreset(name);
        ASSERT_TRUE(s) << name;
        EXPECT_NEAR(fine.toXyz(sampleSpectrum(fine, *s, SpectrumRole::Emission))[1], 1, 2e-3)
            << name;
    }
    // Illuminant A's chromaticity: x = 0.44757, y = 0.40745 (CIE 015:2018 table T.3).
    const auto xyA =
        xyzToXy(fine.toXyz(sampleSpectrum(fine, *illuminantPreset("a"), SpectrumRole::Emission)));
    EXPECT_NEAR(xyA[0], 0.44757, 1e-4);
    EXPECT_NEAR(xyA[1], 0.40745, 1e-4);
    EXPECT_FALSE(illuminantPreset("F13"));
}

TEST(SpectralSpectrum, Blacklight) {
    auto blacklight = illuminantPreset("BlackLight");
    ASSERT_TRUE(blacklight);
    EXPECT_NEAR((*blacklight)(365), 1, 1e-3);  // UV-A peak
    EXPECT_GT((*blacklight)(404.7), 0.05);  // the small violet mercury line
    EXPECT_LT((*blacklight)(404.7), 0.15);
    EXPECT_LT((*blacklight)(450), 1e-6);
    EXPECT_GT(uvPowerFraction(*blacklight), 0.95);
}

TEST(SpectralSpectrum, UvEmitting) {
    const auto uv = [](SpectrumShape shape) { return *isUvEmitting(SpectrumSpec{shape, 1}); };
    EXPECT_TRUE(uv(PresetSpectrum{"blacklight"}));
    EXPECT_TRUE(uv(PresetSpectrum{"D65"}));  // daylight has UV; brighteners rely on it
    EXPECT_FALSE(uv(PresetSpectrum{"A"}));
    EXPECT_FALSE(uv(BlackbodySpectrum{2700}));
    EXPECT_TRUE(uv(GaussianSpectrum{380, 10}));
    EXPECT_FALSE(uv(GaussianSpectrum{550, 10}));
    EXPECT_FALSE(uv(TabulatedSpectrum{{400, 700}, {1, 1}}));
    EXPECT_FALSE(*isUvEmitting(SpectrumSpec{PresetSpectrum{"blacklight"}, 0}));  // switched off
    EXPECT_FALSE(isUvEmitting(SpectrumSpec{PresetSpectrum{"nope"}, 1}));
}

TEST(SpectralSpectrum, RgbEmissionHasTheRgbColour) {
    // Emission RGB maps to a spectrum whose XYZ is the RGB's (Y = its luminance).
    const WavelengthSet fine = fineWavelengths();
    for (Rgb rgb : {Rgb{1, 1, 1}, Rgb{4, 2, 1}, Rgb{0.1, 0.5, 0.05}, Rgb{0, 0, 3}}) {
        auto samples =
            sampleSpectrum(fine, SpectrumSpec{RgbSpectrum{rgb}, 1}, SpectrumRole::Emission);
        ASSERT_TRUE(samples);
        const Rgb back = xyzToLinearSrgb(fine.toXyz(*samples));
        // Within 3e-3 of the largest component. Emission is sampled by hat means, which blur
        // the steep edge of a saturated shape: pure blue comes back 2.6e-3 low (measured).
        const double largest = std::max({rgb[0], rgb[1], rgb[2]});
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(back[c], rgb[c], 3e-3 * largest) << c;
    }
    auto black =
        sampleSpectrum(fine, SpectrumSpec{RgbSpectrum{{0, 0, 0}}, 1}, SpectrumRole::Emission);
    for (double v : *black)
        EXPECT_EQ(v, 0);
}

TEST(SpectralSpectrum, ScaleMultiplies) {
    auto one = makeSpectrum(SpectrumSpec{GaussianSpectrum{500, 20}, 1}, SpectrumRole::Emission);
    auto three = makeSpectrum(SpectrumSpec{GaussianSpectrum{500, 20}, 3}, SpectrumRole::Emission);
    EXPECT_DOUBLE_EQ((*three)(510), 3 * (*one)(510));
}

TEST(SpectralSpectrum, MakeSpectrumRefusesBadSpecs) {
    const auto fails = [](SpectrumSpec spec) {
        return !makeSpectrum(spec, SpectrumRole::Emission).ok();
    };
    EXPECT_TRUE(fails({TabulatedSpectrum{{400, 500}, {1}}, 1}));
    EXPECT_TRUE(fails({TabulatedSpectrum{{500, 400}, {1, 1}}, 1}));
    EXPECT_TRUE(fails({TabulatedSpectrum{{400, 500}, {1, NAN}}, 1}));
    EXPECT_TRUE(fails({TabulatedSpectrum{}, 1}));
    EXPECT_TRUE(fails({PresetSpectrum{"moonlight"}, 1}));
    EXPECT_TRUE(fails({BlackbodySpectrum{0}, 1}));
    EXPECT_TRUE(fails({GaussianSpectrum{500, 0}, 1}));
    EXPECT_TRUE(fails({GaussianSpectrum{NAN, 10}, 1}));
    EXPECT_TRUE(fails({RgbSpectrum{{-1, 0, 0}}, 1}));
    EXPECT_TRUE(fails({GaussianSpectrum{500, 10}, -1}));
    EXPECT_TRUE(fails({GaussianSpectrum{500, 10}, INFINITY}));
}

}  // namespace
}  // namespace daisy
