#include "spectral/wavelength_spec.h"

#include <gtest/gtest.h>

#include "spectral/presets.h"

namespace daisy {
namespace {

TEST(WavelengthSpec, PresetsCaseInsensitive) {
    for (const char* name : {"daisyriot", "meyer4", "visible", "fine", "auto"}) {
        auto spec = parseWavelengthSpec(name);
        ASSERT_TRUE(spec) << name;
        EXPECT_EQ(spec->kind, WavelengthSpec::Kind::Preset);
        EXPECT_EQ(spec->preset, name);
    }
    auto upper = parseWavelengthSpec("DaisyRiot");
    ASSERT_TRUE(upper);
    EXPECT_EQ(upper->preset, "daisyriot");
}

TEST(WavelengthSpec, Range) {
    auto spec = parseWavelengthSpec("350:650:50");
    ASSERT_TRUE(spec);
    EXPECT_EQ(spec->kind, WavelengthSpec::Kind::Range);
    EXPECT_DOUBLE_EQ(spec->startNm, 350);
    EXPECT_DOUBLE_EQ(spec->endNm, 650);
    EXPECT_DOUBLE_EQ(spec->stepNm, 50);
}

TEST(WavelengthSpec, List) {
    auto spec = parseWavelengthSpec("456.4,490.9,557.7,631.4");
    ASSERT_TRUE(spec);
    EXPECT_EQ(spec->kind, WavelengthSpec::Kind::List);
    ASSERT_EQ(spec->listNm.size(), 4u);
    EXPECT_DOUBLE_EQ(spec->listNm[2], 557.7);
}

TEST(WavelengthSpec, RejectsBadSets) {
    for (const char* bad :
         {"", "rgb", "400:300:10", "400:500:0", "400:500", "1:2:3:4", "500,400", "400,400",
          "100,500", "400,,500", "400:3000:10", "380:780:0.001", "nan"}) {
        EXPECT_FALSE(parseWavelengthSpec(bad)) << bad;
    }
}

TEST(Presets, CanonicalNames) {
    EXPECT_EQ(canonicalIlluminantPreset("d65").value(), "D65");
    EXPECT_EQ(canonicalIlluminantPreset("f12").value(), "F12");
    EXPECT_EQ(canonicalIlluminantPreset("BlackLight").value(), "blacklight");
    EXPECT_FALSE(canonicalIlluminantPreset("F13"));
    EXPECT_EQ(canonicalFluorophorePreset("Rhodamine6G").value(), "rhodamine6g");
    EXPECT_FALSE(canonicalFluorophorePreset("eosin"));
    EXPECT_EQ(illuminantPresetNames().size(), 16u);
}

}  // namespace
}  // namespace daisy
