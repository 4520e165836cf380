#include "spectral/fluorescence.h"

#include <gtest/gtest.h>

#include <cmath>

#include "spectral/spectrum.h"

namespace daisy {
namespace {

bool contains(const Error& error, const std::string& text) {
    return error.message.find(text) != std::string::npos;
}

std::vector<double> filled(const WavelengthSet& set, double value) {
    return std::vector<double>(set.size(), value);
}

// Emission: a Gaussian at 600 nm (any shape with power above every excitation sample).
std::vector<double> emissionShape(const WavelengthSet& set) {
    return sampleSpectrum(set, Spectrum::gaussians({{600, 80, 1}}), SpectrumRole::Emission);
}

// DESIGN.md section 5: quantum yield 1 and full absorption conserve photons exactly; the
// photon count per bin is power * wavelength.
TEST(Fluorescence, FullAbsorptionAndUnitYieldConservePhotons) {
    for (const WavelengthSet& set : {fineWavelengths(), daisyriotWavelengths(),
                                     withUvExcitation(visibleWavelengths(), true, true)}) {
        const std::vector<double> e = emissionShape(set);
        auto m = reradiationMatrix(set, filled(set, 0), filled(set, 1), e, 1.0, "test");
        ASSERT_TRUE(m) << m.error().message;
        for (std::size_t i = 0; i + 1 < set.size(); ++i) {
            double photons = 0;
            for (std::size_t o = 0; o < set.size(); ++o) {
                photons += (*m)(o, i) * set.binWidthNm(o) / set.binWidthNm(i) *
                    set.wavelengthNm(o) / set.wavelengthNm(i);
            }
            EXPECT_NEAR(photons, 1, 1e-12) << set.name() << " at " << set.wavelengthNm(i);
            EXPECT_EQ((*m)(i, i), 0);
        }
        // The last sample has nothing longer to emit into: its absorbed light is lost.
        EXPECT_EQ(m->powerColumnSum(set, set.size() - 1), 0);
    }
}

TEST(Fluorescence, EnergyIsLostExactlyAsTheParametersSay) {
    // c_i = rho_i + Q a_i sum_o p_i(o) l_i / l_o: reflection plus the Stokes-shifted yield.
    const WavelengthSet set = visibleWavelengths();
    const std::vector<double> e = emissionShape(set);
    const double rho = 0.3, a = 0.5, q = 0.8;
    auto m = reradiationMatrix(set, filled(set, rho), filled(set, a), e, q, "test");
    ASSERT_TRUE(m);
    for (std::size_t i = 0; i + 1 < set.size(); ++i) {
        double emitted = 0, stokes = 0;
        for (std::size_t o = i + 1; o < set.size(); ++o) {
            emitted += e[o] * set.binWidthNm(o);
            stokes += e[o] * set.binWidthNm(o) * set.wavelengthNm(i) / set.wavelengthNm(o);
        }
        const double expected = rho + q * a * stokes / emitted;
        EXPECT_NEAR(m->powerColumnSum(set, i), expected, 1e-12);
        EXPECT_LT(m->powerColumnSum(set, i), rho + q * a);  // Stokes loss is strictly positive
        EXPECT_DOUBLE_EQ((*m)(i, i), rho);
    }
    EXPECT_TRUE(validateReradiationMatrix(set, *m, "test"));
}

TEST(Fluorescence, LowerTriangularAndRenormalisedAboveEachInput) {
    const WavelengthSet set = daisyriotWavelengths();
    // Emission spread over the whole set, including below some inputs.
    const std::vector<double> e = filled(set, 1.0);
    auto m = reradiationMatrix(set, filled(set, 0), filled(set, 1), e, 1, "test");
    ASSERT_TRUE(m);
    for (std::size_t o = 0; o < set.size(); ++o) {
        for (std::size_t i = o + 1; i < set.size(); ++i)
            EXPECT_EQ((*m)(o, i), 0);
    }
    // From 550 nm only 600 and 650 receive: p(600) = w_600 / (w_600 + w_650) = 50 / 255.
    const double p600 = 50.0 / (50 + 205);
    EXPECT_NEAR((*m)(5, 4), p600 * (550.0 / 600) * (50.0 / 50), 1e-12);
}

TEST(Fluorescence, NonFluorescentMaterialIsDiagonal) {
    const WavelengthSet set = visibleWavelengths();
    auto m = materialReradiationMatrix(set, std::nullopt, {0.5, 0.5, 0.5}, std::nullopt, "grey");
    ASSERT_TRUE(m);
    EXPECT_TRUE(m->isDiagonal());
    for (std::size_t i = 0; i < set.size(); ++i)
        EXPECT_NEAR((*m)(i, i), 0.5, 1e-12);
    auto tabulated =
        materialReradiationMatrix(set, SpectrumSpec{TabulatedSpectrum{{400, 700}, {0.2, 0.8}}},
                                  {0, 0, 0}, std::nullopt, "ramp");
    ASSERT_TRUE(tabulated);
    EXPECT_NEAR((*tabulated)(0, 0), 0.2, 1e-12);
    EXPECT_NEAR((*tabulated)(15, 15), 0.8, 1e-12);
}

TEST(Fluorescence, PresetsAreValidOnEveryPreset) {
    const std::vector<WavelengthSet> sets = {daisyriotWavelengths(), meyer4Wavelengths(),
                                             visibleWavelengths(), fineWavelengths(),
                                             withUvExcitation(visibleWavelengths(), true, true)};
    for (const FluorophoreData& data : fluorophoreData()) {
        for (const WavelengthSet& set : sets) {
            auto m = materialReradiationMatrix(set, std::nullopt, {0.8, 0.8, 0.8},
                                               FluorophorePreset{std::string(data.name)}, "paint");
            ASSERT_TRUE(m) << data.name << " on " << set.name() << ": " << m.error().message;
            for (std::size_t i = 0; i < set.size(); ++i)
                EXPECT_LE(m->powerColumnSum(set, i), 1 + 1e-12);
        }
    }
}

TEST(Fluorescence, PresetPeaks) {
    // Fluorescein on the fine set: absorbs most at 490 nm and re-emits most at 515 nm.
    const WavelengthSet fine = fineWavelengths();
    auto params = fluorophorePresetParams("Fluorescein");
    ASSERT_TRUE(params);
    EXPECT_DOUBLE_EQ(params->quantumYield, 0.93);
    auto m = materialReradiationMatrix(fine, std::nullopt, {0, 0, 0},
                                       FluorophorePreset{"fluorescein"}, "dye");
    ASSERT_TRUE(m);
    const std::size_t at490 = (490 - 360) / 5;
    std::size_t brightest = 0;
    for (std::size_t o = 0; o < fine.size(); ++o) {
        if ((*m)(o, at490) > (*m)(brightest, at490)) brightest = o;
    }
    EXPECT_DOUBLE_EQ(fine.wavelengthNm(brightest), 515);
    EXPECT_FALSE(fluorophorePresetParams("eosin"));
    auto unknown = materialReradiationMatrix(fine, std::nullopt, {0, 0, 0},
                                             FluorophorePreset{"eosin"}, "scene.gltf: paint");
    ASSERT_FALSE(unknown);
    EXPECT_TRUE(contains(unknown.error(), "scene.gltf: paint"));
}

TEST(Fluorescence, PresetLayerKeepsRhoPlusAWithinOne) {
    // A preset over a white base colour: rho = base (1 - a), so rho + a <= 1 everywhere.
    const WavelengthSet fine = fineWavelengths();
    auto m = materialReradiationMatrix(fine, std::nullopt, {1, 1, 1},
                                       FluorophorePreset{"rhodamine6g"}, "white paint");
    ASSERT_TRUE(m);
    const std::size_t at530 = (530 - 360) / 5;
    EXPECT_NEAR((*m)(at530, at530), 1 - 0.8, 1e-6);  // peak absorption 0.8 at 530 nm
}

TEST(Fluorescence, FluorescentColorGlowsWithItsColour) {
    // Under UV only (365 nm), the re-emitted light has the chromaticity of Ks.
    const WavelengthSet set = withUvExcitation(fineWavelengths(), true, true);
    const FluorescentColor ks{{0.9, 0.45, 0.0}};
    EXPECT_DOUBLE_EQ(fluorescentColorFluorophore(ks).quantumYield, 0.9);
    auto m = materialReradiationMatrix(set, std::nullopt, {0.2, 0.2, 0.2}, ks, "sign");
    ASSERT_TRUE(m) << m.error().message;
    const std::size_t at365 = (365 - 360) / 5 + 2;  // after the added 320 and 340
    ASSERT_DOUBLE_EQ(set.wavelengthNm(at365), 365);
    std::vector<double> glow(set.size());
    for (std::size_t o = at365 + 1; o < set.size(); ++o)
        glow[o] = (*m)(o, at365);
    const Rgb rgb = xyzToLinearSrgb(set.toXyz(glow));
    EXPECT_NEAR(rgb[1] / rgb[0], 0.5, 0.02);
    EXPECT_NEAR(rgb[2] / rgb[0], 0.0, 0.02);
    // The visible reflectance is the base colour (no absorption above 420 nm).
    const std::size_t at550 = set.size() - 1 - (830 - 550) / 5;
    EXPECT_NEAR((*m)(at550, at550), 0.2, 1e-9);
}

TEST(Fluorescence, ExplicitMatrixOnItsOwnGridIsExact) {
    const FluorescenceMatrix measured{{400, 500, 600},
                                      {{0.5, 0, 0}, {0.2, 0.6, 0}, {0.1, 0.1, 0.7}}};
    auto set = WavelengthSet::fromWavelengths({400, 500, 600}, "grid");
    ASSERT_TRUE(set);
    auto m = materialReradiationMatrix(*set, std::nullopt, {1, 1, 1}, measured, "measured");
    ASSERT_TRUE(m) << m.error().message;
    // Power fractions become densities: M = F w_i / w_o (w = 40 + 50, 100, 50 + 230).
    const double w[] = {40 + 50, 100, 50 + 230};
    for (std::size_t o = 0; o < 3; ++o) {
        for (std::size_t i = 0; i <= o; ++i)
            EXPECT_NEAR((*m)(o, i), measured.values[o][i] * w[i] / w[o], 1e-12) << o << i;
    }
    for (std::size_t i = 0; i < 3; ++i) {
        double sum = 0;
        for (std::size_t o = 0; o < 3; ++o)
            sum += measured.values[o][i];
        EXPECT_NEAR(m->powerColumnSum(*set, i), sum, 1e-12);
    }
}

TEST(Fluorescence, ExplicitMatrixResampledConservesColumnPower) {
    const FluorescenceMatrix measured{{400, 500, 600},
                                      {{0.5, 0, 0}, {0.2, 0.6, 0}, {0.1, 0.1, 0.7}}};
    const WavelengthSet fine = fineWavelengths();
    auto m = resampleFluorescenceMatrix(fine, measured, "measured");
    ASSERT_TRUE(m) << m.error().message;
    // At 450 nm, halfway between the columns of 400 and 500: reflectance 0.55, and the
    // power re-radiated is the mean of the columns' off-diagonal sums, (0.3 + 0.1) / 2.
    const std::size_t at450 = (450 - 360) / 5;
    EXPECT_NEAR(m->powerColumnSum(fine, at450), 0.55 + 0.2, 1e-12);
    // Outside the matrix's range only the end reflectance remains.
    EXPECT_NEAR((*m)(0, 0), 0.5, 1e-12);
    EXPECT_NEAR(m->powerColumnSum(fine, 0), 0.5, 1e-12);
}

// Every refusal names the material and, where there is one, the wavelength.
TEST(Fluorescence, ValidationRefusesRhoPlusAOverOne) {
    const WavelengthSet set = visibleWavelengths();
    std::vector<double> a = filled(set, 0);
    a[5] = 0.4;  // 500 nm
    auto m = reradiationMatrix(set, filled(set, 0.8), a, emissionShape(set), 0.9,
                               "scene.gltf: materials[3] 'paint'");
    ASSERT_FALSE(m);
    EXPECT_TRUE(contains(m.error(), "scene.gltf: materials[3] 'paint'"));
    EXPECT_TRUE(contains(m.error(), "at 500 nm"));
    EXPECT_TRUE(contains(m.error(), "1.2"));
    // The same through the material builder with explicit parameters (no layering).
    FluorescenceParams params;
    params.absorption = SpectrumSpec{GaussianSpectrum{500, 30}, 0.5};
    params.emission = SpectrumSpec{GaussianSpectrum{560, 30}};
    params.quantumYield = 0.9;
    auto material = materialReradiationMatrix(set, std::nullopt, {0.8, 0.8, 0.8}, params, "ink");
    ASSERT_FALSE(material);
    EXPECT_TRUE(contains(material.error(), "ink: reflectance"));
}

TEST(Fluorescence, ValidationRefusesOutOfRangeInputs) {
    const WavelengthSet set = visibleWavelengths();
    const std::vector<double> e = emissionShape(set);
    std::vector<double> bad = filled(set, 0.2);
    bad[2] = 1.5;  // 440 nm
    auto rho = reradiationMatrix(set, bad, filled(set, 0), e, 1, "m1");
    ASSERT_FALSE(rho);
    EXPECT_TRUE(contains(rho.error(), "m1: reflectance 1.5 at 440 nm"));
    auto absorption = reradiationMatrix(set, filled(set, 0), bad, e, 1, "m2");
    ASSERT_FALSE(absorption);
    EXPECT_TRUE(contains(absorption.error(), "m2: fluorophore absorption 1.5 at 440 nm"));
    std::vector<double> negative = e;
    negative[3] = -1;
    auto emission = reradiationMatrix(set, filled(set, 0), filled(set, 0.5), negative, 1, "m3");
    ASSERT_FALSE(emission);
    EXPECT_TRUE(contains(emission.error(), "m3: fluorescence emission -1 at 460 nm"));
    for (double q : {-0.1, 1.1, double(NAN)}) {
        auto yield = reradiationMatrix(set, filled(set, 0), filled(set, 0.5), e, q, "m4");
        ASSERT_FALSE(yield);
        EXPECT_TRUE(contains(yield.error(), "m4: quantum yield"));
    }
    auto badSpec = materialReradiationMatrix(
        set, std::nullopt, {0, 0, 0},
        FluorescenceParams{SpectrumSpec{GaussianSpectrum{500, -3}}, SpectrumSpec{}, 1}, "m5");
    ASSERT_FALSE(badSpec);
    EXPECT_TRUE(contains(badSpec.error(), "m5: fluorescence absorption"));
    auto badEmissionSpec =
        materialReradiationMatrix(set, std::nullopt, {0, 0, 0},
                                  FluorescenceParams{SpectrumSpec{GaussianSpectrum{500, 3}},
                                                     SpectrumSpec{PresetSpectrum{"none"}}, 1},
                                  "m6");
    ASSERT_FALSE(badEmissionSpec);
    EXPECT_TRUE(contains(badEmissionSpec.error(), "m6: fluorescence emission"));
    auto badReflectance = materialReradiationMatrix(
        set, SpectrumSpec{TabulatedSpectrum{{400, 500}, {0.5}}}, {0, 0, 0}, std::nullopt, "m7");
    ASSERT_FALSE(badReflectance);
    EXPECT_TRUE(contains(badReflectance.error(), "m7: reflectance"));
    auto overOne =
        materialReradiationMatrix(set, SpectrumSpec{TabulatedSpectrum{{400, 500}, {0.5, 1.5}}},
                                  {0, 0, 0}, std::nullopt, "m8");
    ASSERT_FALSE(overOne);
    EXPECT_TRUE(contains(overOne.error(), "m8: reflectance 1.1 at 460 nm"));
}

TEST(Fluorescence, ValidationRefusesBadMatrices) {
    const WavelengthSet set = daisyriotWavelengths();
    const std::size_t m = set.size();
    const auto make = [&] {
        ReradiationMatrix matrix;
        matrix.size = m;
        matrix.values.assign(m * m, 0.0);
        for (std::size_t i = 0; i < m; ++i)
            matrix(i, i) = 0.5;
        return matrix;
    };
    EXPECT_TRUE(validateReradiationMatrix(set, make(), "ok"));

    ReradiationMatrix upper = make();
    upper(1, 3) = 0.1;  // 500 nm -> 400 nm
    auto e1 = validateReradiationMatrix(set, upper, "lamp shade");
    ASSERT_FALSE(e1);
    EXPECT_TRUE(contains(e1.error(),
                         "lamp shade: re-radiation 0.1 from 500 nm to the shorter "
                         "400 nm"));

    ReradiationMatrix negative = make();
    negative(4, 2) = -0.1;
    auto e2 = validateReradiationMatrix(set, negative, "m");
    ASSERT_FALSE(e2);
    EXPECT_TRUE(contains(e2.error(), "from 450 nm to 550 nm is -0.1"));

    ReradiationMatrix infinite = make();
    infinite(2, 2) = INFINITY;
    EXPECT_FALSE(validateReradiationMatrix(set, infinite, "m"));

    ReradiationMatrix creates = make();
    creates(3, 2) = 0.6;  // 450 -> 500 nm; w equal, so the column sums to 1.1
    auto e3 = validateReradiationMatrix(set, creates, "glow");
    ASSERT_FALSE(e3);
    EXPECT_TRUE(contains(e3.error(), "glow: light at 450 nm leaves with 1.1 times its power"));

    ReradiationMatrix small = make();
    small.size = 3;
    small.values.resize(9);
    auto e4 = validateReradiationMatrix(set, small, "m");
    ASSERT_FALSE(e4);
    EXPECT_TRUE(contains(e4.error(), "daisyriot"));
}

TEST(Fluorescence, ValidationRefusesBadMeasuredMatrices) {
    const auto refused = [](FluorescenceMatrix matrix, const std::string& text) {
        auto result = resampleFluorescenceMatrix(visibleWavelengths(), matrix, "measured");
        if (result) return ::testing::AssertionFailure() << "accepted";
        if (!contains(result.error(), "measured: ") || !contains(result.error(), text)) {
            return ::testing::AssertionFailure() << result.error().message;
        }
        return ::testing::AssertionSuccess();
    };
    EXPECT_TRUE(refused({{}, {}}, "no wavelengths"));
    EXPECT_TRUE(refused({{500, 400}, {{0, 0}, {0, 0}}}, "400 nm is not finite and strictly"));
    EXPECT_TRUE(refused({{400, 500}, {{0, 0}}}, "1 rows for 2 wavelengths"));
    EXPECT_TRUE(refused({{400, 500}, {{0, 0}, {0}}}, "row 1 (500 nm) has 1 values"));
    EXPECT_TRUE(refused({{400, 500}, {{0, 0}, {-1, 0}}}, "from 400 nm to 500 nm is -1"));
    EXPECT_TRUE(
        refused({{400, 500}, {{0.5, 0.1}, {0, 0.5}}}, "0.1 from 500 nm to the shorter 400"));
    EXPECT_TRUE(refused({{400, 500}, {{0.7, 0}, {0.4, 0.5}}}, "column at 400 nm sums to 1.1"));
}

TEST(Fluorescence, MaterialEmission) {
    const WavelengthSet set = visibleWavelengths();
    auto none = materialEmission(set, std::nullopt, {0, 0, 0}, "wall");
    ASSERT_TRUE(none);
    for (double v : *none)
        EXPECT_EQ(v, 0);
    auto rgb = materialEmission(set, std::nullopt, {1, 1, 1}, "lamp");
    ASSERT_TRUE(rgb);
    EXPECT_NEAR(set.toXyz(*rgb)[1], 1, 5e-3);  // Y of RGB white is 1
    auto blacklight =
        materialEmission(set, SpectrumSpec{PresetSpectrum{"blacklight"}, 20}, {0, 0, 0}, "uv lamp");
    ASSERT_TRUE(blacklight);
    EXPECT_GT((*blacklight)[0], 0);  // the 400 nm sample gets the flat end of the 365 nm peak
    auto bad = materialEmission(set, SpectrumSpec{BlackbodySpectrum{-5}}, {0, 0, 0}, "bulb");
    ASSERT_FALSE(bad);
    EXPECT_TRUE(contains(bad.error(), "bulb: emission: blackbody temperature -5 K"));
}

}  // namespace
}  // namespace daisy
