#include "spectral/wavelength_set.h"

#include <gtest/gtest.h>

#include <numeric>

#include "spectral/cie_tables.h"
#include "spectral/spectrum.h"

namespace daisy {
namespace {

// Sums of the columns of the 1 nm CIE 1931 table in assets/reference/ (Python math.fsum over
// the CSV); pbrt-v4 quotes 106.856895 for ybar from another printing of the same table.
constexpr double kXbarSum = 106.865469489595;
constexpr double kYbarSum = 106.8569171011719;
constexpr double kZbarSum = 106.892251278636;

std::vector<WavelengthSet> presets() {
    return {daisyriotWavelengths(), meyer4Wavelengths(), visibleWavelengths(), fineWavelengths()};
}

TEST(WavelengthSet, Presets) {
    const WavelengthSet daisyriot = daisyriotWavelengths();
    EXPECT_EQ(daisyriot.wavelengthsNm(), (std::vector<double>{350, 400, 450, 500, 550, 600, 650}));
    EXPECT_EQ(meyer4Wavelengths().wavelengthsNm(),
              (std::vector<double>{456.4, 490.9, 557.7, 631.4}));
    EXPECT_EQ(visibleWavelengths().size(), 16u);
    const WavelengthSet fine = fineWavelengths();
    EXPECT_EQ(fine.size(), 95u);
    EXPECT_DOUBLE_EQ(fine.wavelengthNm(0), 360);
    EXPECT_DOUBLE_EQ(fine.wavelengthNm(94), 830);
}

TEST(WavelengthSet, CmfIntegralsMatchTabulatedSums) {
    // The hats sum to 1 on the CIE range, so each column of the m x 3 matrix sums to the
    // table's own sum (divided by the ybar sum), whatever the set.
    EXPECT_NEAR(cieYIntegral(), kYbarSum, 1e-9);
    EXPECT_NEAR(cieYIntegral(), 106.856895, 1e-4);
    for (const WavelengthSet& set : presets()) {
        std::array<double, 3> sum{0, 0, 0};
        for (std::size_t k = 0; k < set.size(); ++k) {
            for (int c = 0; c < 3; ++c)
                sum[c] += set.xyzWeights(k)[c];
        }
        EXPECT_NEAR(sum[0] * kYbarSum, kXbarSum, 1e-9) << set.name();
        EXPECT_NEAR(sum[1] * kYbarSum, kYbarSum, 1e-9) << set.name();
        EXPECT_NEAR(sum[2] * kYbarSum, kZbarSum, 1e-9) << set.name();
    }
}

TEST(WavelengthSet, D65WhitePointOnFineSet) {
    // CIE 015:2018 table T.3: D65 is x = 0.31272, y = 0.32903 (rounded: 0.3127, 0.3290).
    const WavelengthSet fine = fineWavelengths();
    auto d65 = illuminantPreset("D65");
    ASSERT_TRUE(d65);
    const auto xy = xyzToXy(fine.toXyz(sampleSpectrum(fine, *d65, SpectrumRole::Emission)));
    EXPECT_NEAR(xy[0], 0.3127, 1e-4);
    EXPECT_NEAR(xy[1], 0.3290, 1e-4);
}

TEST(WavelengthSet, HatsArePartitionOfUnity) {
    for (const WavelengthSet& set : presets()) {
        for (double nm = set.domainStartNm(); nm <= set.domainEndNm(); nm += 0.7) {
            double sum = 0;
            for (std::size_t k = 0; k < set.size(); ++k) {
                EXPECT_GE(set.hat(k, nm), 0);
                sum += set.hat(k, nm);
            }
            EXPECT_NEAR(sum, 1, 1e-12) << set.name() << " at " << nm;
        }
        const double widths =
            std::accumulate(set.binWidthsNm().begin(), set.binWidthsNm().end(), 0.0);
        EXPECT_NEAR(widths, set.domainEndNm() - set.domainStartNm(), 1e-9) << set.name();
        EXPECT_DOUBLE_EQ(set.hat(0, set.wavelengthNm(0)), 1);
    }
}

TEST(WavelengthSet, EndsExtendToTheCieRange) {
    const WavelengthSet meyer = meyer4Wavelengths();
    EXPECT_DOUBLE_EQ(meyer.domainStartNm(), 360);
    EXPECT_DOUBLE_EQ(meyer.domainEndNm(), 830);
    EXPECT_DOUBLE_EQ(meyer.hat(0, 400), 1);  // flat below the first sample
    EXPECT_DOUBLE_EQ(meyer.hat(3, 800), 1);  // flat above the last
    EXPECT_DOUBLE_EQ(meyer.binWidthNm(0), 456.4 - 360 + (490.9 - 456.4) / 2);
    const WavelengthSet daisyriot = daisyriotWavelengths();
    EXPECT_DOUBLE_EQ(daisyriot.domainStartNm(), 350);  // the first sample is below 360
    EXPECT_DOUBLE_EQ(daisyriot.binWidthNm(0), 25);
    EXPECT_DOUBLE_EQ(daisyriot.binWidthNm(6), 25 + 180);
}

TEST(WavelengthSet, FromSpec) {
    auto range = makeWavelengthSet(*parseWavelengthSpec("400:700:100"));
    ASSERT_TRUE(range);
    EXPECT_EQ(range->wavelengthsNm(), (std::vector<double>{400, 500, 600, 700}));
    EXPECT_EQ(range->name(), "400:700:100");
    // The end is included only when the step lands on it.
    auto partial = makeWavelengthSet(*parseWavelengthSpec("400:650:100"));
    ASSERT_TRUE(partial);
    EXPECT_EQ(partial->wavelengthsNm(), (std::vector<double>{400, 500, 600}));
    // No accumulated rounding: 380 + 40 * 10 is exactly 780.
    auto tenths = makeWavelengthSet(*parseWavelengthSpec("380:780:0.1"));
    ASSERT_TRUE(tenths);
    EXPECT_EQ(tenths->size(), 4001u);
    EXPECT_DOUBLE_EQ(tenths->wavelengthNm(4000), 780);
    auto list = makeWavelengthSet(*parseWavelengthSpec("450,550,650"));
    ASSERT_TRUE(list);
    EXPECT_EQ(list->size(), 3u);
    for (const char* name : {"daisyriot", "meyer4", "visible", "fine"}) {
        auto set = makeWavelengthSet(*parseWavelengthSpec(name));
        ASSERT_TRUE(set) << name;
        EXPECT_EQ(set->name(), name);
    }
}

TEST(WavelengthSet, UvIsAddedOnlyWhenBothFactsHold) {
    const WavelengthSpec spec = *parseWavelengthSpec("auto");
    for (bool uv : {false, true}) {
        for (bool fluorescent : {false, true}) {
            auto set = makeWavelengthSet(spec, uv, fluorescent);
            ASSERT_TRUE(set);
            if (uv && fluorescent) {
                EXPECT_EQ(set->size(), 31u + 4);
                EXPECT_DOUBLE_EQ(set->wavelengthNm(0), 320);
                EXPECT_DOUBLE_EQ(set->wavelengthNm(4), 400);
                EXPECT_DOUBLE_EQ(set->wavelengthNm(5), 410);
                EXPECT_EQ(set->name(), "400:700:10+uv");
            } else {
                EXPECT_EQ(set->wavelengthsNm(), autoWavelengths().wavelengthsNm());
                EXPECT_EQ(set->size(), 31u);
            }
        }
    }
    // Only UV samples more than 10 nm below the base's first sample are added.
    const WavelengthSet withUv = withUvExcitation(daisyriotWavelengths(), true, true);
    EXPECT_EQ(withUv.wavelengthsNm().front(), 320);
    EXPECT_EQ(withUv.size(), 8u);
    EXPECT_EQ(withUvExcitation(fineWavelengths(), true, true).size(), 97u);
    // Presets and ranges follow the same rule; an explicit list is exact.
    EXPECT_EQ(makeWavelengthSet(*parseWavelengthSpec("fine"), true, true)->size(), 97u);
    EXPECT_EQ(makeWavelengthSet(*parseWavelengthSpec("fine"), true, false)->size(), 95u);
    EXPECT_EQ(makeWavelengthSet(*parseWavelengthSpec("400:700:10"), true, true)->size(), 35u);
    EXPECT_EQ(makeWavelengthSet(*parseWavelengthSpec("450,550,650"), true, true)->size(), 3u);
}

TEST(WavelengthSet, RefusesBadWavelengths) {
    EXPECT_FALSE(WavelengthSet::fromWavelengths({}, "empty"));
    EXPECT_FALSE(WavelengthSet::fromWavelengths({500, 400}, "descending"));
    EXPECT_FALSE(WavelengthSet::fromWavelengths({500, 500}, "repeated"));
    auto outside = WavelengthSet::fromWavelengths({100, 500}, "mine");
    ASSERT_FALSE(outside);
    EXPECT_NE(outside.error().message.find("mine"), std::string::npos);
    EXPECT_NE(outside.error().message.find("100 nm"), std::string::npos);
    WavelengthSpec unknown;
    unknown.preset = "rgb";
    EXPECT_FALSE(makeWavelengthSet(unknown));
}

TEST(WavelengthSet, SingleSampleCoversEverything) {
    auto one = WavelengthSet::fromWavelengths({550}, "one");
    ASSERT_TRUE(one);
    EXPECT_DOUBLE_EQ(one->hat(0, 360), 1);
    EXPECT_DOUBLE_EQ(one->hat(0, 830), 1);
    EXPECT_DOUBLE_EQ(one->binWidthNm(0), 470);
    // A flat spectrum of value 1 has Y = 1 (the matrix's normalisation).
    EXPECT_NEAR(one->toXyz(std::vector<double>{1.0})[1], 1, 1e-12);
}

}  // namespace
}  // namespace daisy
