// What the viewer draws per vertex (viewer/display_values.h), on a hand-made snapshot whose
// values are known: the channel layout of pipeline/channel_layout.h, the false-colour
// scalar, and the automatic range's rule.
#if DAISY_HAVE_VIEWER
#include "viewer/display_values.h"

#include <gtest/gtest.h>

#include <cmath>

namespace daisy::viewer {
namespace {

// Two patches, m = 2 samples: channels L0 L1 X Y Z 1. Corner c of patch p has L0 = 10p + c + 1,
// L1 = 100 (p + 1), X = 1, Y = 2^(p * 3 + c) / 1000, Z = 3; the patch values are the corners'
// first.
DisplaySnapshot snapshot() {
    DisplaySnapshot s;
    s.wavelengthCount = 2;
    s.layout = {2, true};
    s.wavelengthsNm = {365, 550};
    for (int p = 0; p < 2; ++p) {
        for (int c = 0; c < 3; ++c) {
            const float y = std::pow(2.0f, float(p * 3 + c)) / 1000;
            const float values[6] = {float(10 * p + c + 1), float(100 * (p + 1)), 1, y, 3, 1};
            s.corners.insert(s.corners.end(), values, values + 6);
            if (c == 0) s.patchValues.insert(s.patchValues.end(), values, values + 6);
        }
    }
    return s;
}

TEST(DisplayValues, SmoothLuminanceTakesEveryCornerAndItsRange) {
    std::vector<float> values;
    const FalseRange range = displayValues(snapshot(), DisplaySettings{}, values);
    ASSERT_EQ(values.size(), 2u * 3 * 4);
    for (int v = 0; v < 6; ++v) {
        EXPECT_EQ(values[v * 4 + 0], 1);
        EXPECT_FLOAT_EQ(values[v * 4 + 1], std::pow(2.0f, float(v)) / 1000);
        EXPECT_EQ(values[v * 4 + 2], 3);
        EXPECT_FLOAT_EQ(values[v * 4 + 3], values[v * 4 + 1]);  // luminance = Y
    }
    // Largest Y = 32e-3, smallest 1e-3: 1.5 decades, under the 4-decade cap.
    EXPECT_NEAR(range.hi, std::log10(0.032), 1e-6);
    EXPECT_NEAR(range.lo, std::log10(0.001), 1e-6);
}

TEST(DisplayValues, FlatWavelengthUsesThePatchValueAtTheSample) {
    DisplaySettings settings;
    settings.quantity = DisplayQuantity::Wavelength;
    settings.wavelengthIndex = 0;  // the UV sample
    settings.smooth = false;
    std::vector<float> values;
    const FalseRange range = displayValues(snapshot(), settings, values);
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(values[c * 4 + 3], 1);  // patch 0's L0
        EXPECT_EQ(values[(3 + c) * 4 + 3], 11);  // patch 1's L0
    }
    EXPECT_NEAR(range.hi, std::log10(11.0), 1e-6);
    EXPECT_NEAR(range.lo, 0.0, 1e-6);
    settings.autoRange = false;
    settings.falseLo = -2;
    settings.falseHi = 5;
    const FalseRange fixed = displayValues(snapshot(), settings, values);
    EXPECT_EQ(fixed.lo, -2);
    EXPECT_EQ(fixed.hi, 5);
}

TEST(DisplayValues, ParseDisplayAndNearestSample) {
    auto choice = parseDisplay("wavelength:370,flat,wireframe");
    ASSERT_TRUE(choice) << choice.error().message;
    EXPECT_EQ(choice->settings.quantity, DisplayQuantity::Wavelength);
    EXPECT_FALSE(choice->settings.smooth);
    EXPECT_TRUE(choice->wireframe);
    ASSERT_TRUE(choice->wavelengthNm);
    EXPECT_EQ(nearestSample({320, 365, 400, 410}, *choice->wavelengthNm), 1u);
    EXPECT_EQ(nearestSample({320, 365, 400, 410}, 1000), 3u);
    EXPECT_FALSE(parseDisplay("wavelength:blue"));
    EXPECT_FALSE(parseDisplay("colour,,flat"));
    auto luminance = parseDisplay("luminance");
    ASSERT_TRUE(luminance);
    EXPECT_EQ(luminance->settings.quantity, DisplayQuantity::Luminance);
}

}  // namespace
}  // namespace daisy::viewer
#endif
