#include "image/exposure.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "spectral/color.h"

namespace daisy {
namespace {

// An XYZ image of `count` pixels with the D65 white's chromaticity (linear sRGB grey) and the
// given luminances.
Image greyImage(const std::vector<float>& luminances) {
    const Xyz white = linearSrgbToXyz({1, 1, 1});
    Image image(int(luminances.size()), 1, 3);
    for (std::size_t i = 0; i < luminances.size(); ++i) {
        for (int c = 0; c < 3; ++c)
            image.at(int(i), 0)[c] = static_cast<float>(white[c] * luminances[i]);
    }
    return image;
}

TEST(ImageExposure, ParsesAutoAndStops) {
    EXPECT_TRUE(parseExposure("auto")->automatic);
    EXPECT_TRUE(parseExposure("AUTO")->automatic);
    const auto fixed = parseExposure("-1.5");
    ASSERT_TRUE(fixed.ok());
    EXPECT_FALSE(fixed->automatic);
    EXPECT_EQ(fixed->ev, -1.5);
    EXPECT_EQ(parseExposure("2")->ev, 2);
    for (const char* bad : {"", "abc", "1.5x", "nan", "inf", " 1"}) {
        const auto error = parseExposure(bad);
        ASSERT_FALSE(error.ok()) << bad;
        EXPECT_NE(error.error().message.find(std::string("\"") + bad + "\""), std::string::npos);
    }
}

// Fixed exposure: EV stops are powers of two.
TEST(ImageExposure, FixedEvScalesByPowersOfTwo) {
    const Image image = greyImage({1});
    EXPECT_EQ(exposureScale(Exposure{false, 2}, image), 4);
    EXPECT_EQ(exposureScale(Exposure{false, -1}, image), 0.5);
    EXPECT_EQ(exposureScale(Exposure{false, 0}, image), 1);
}

// A uniform image's log-average luminance is its luminance, mapped to the key 0.18.
TEST(ImageExposure, AutoMapsUniformLuminanceToMiddleGrey) {
    const Image image = greyImage(std::vector<float>(50, 0.5f));
    EXPECT_NEAR(autoExposureScale(image) * 0.5, 0.18, 1e-6);
    // Background pixels (Y = 0 exactly) do not count.
    std::vector<float> withBackground(50, 0.5f);
    withBackground.resize(100, 0.0f);
    EXPECT_NEAR(autoExposureScale(greyImage(withBackground)) * 0.5, 0.18, 1e-6);
    // Log average of 0.02 and 0.5 is 0.1 (and 0.5 x 1.8 does not clip).
    EXPECT_NEAR(autoExposureScale(greyImage({0.02f, 0.5f, 0.02f, 0.5f})), 0.18 / 0.1, 1e-5);
    EXPECT_EQ(autoExposureScale(greyImage({0, 0, 0})), 1);
    EXPECT_EQ(exposureScale(Exposure{}, image), autoExposureScale(image));
}

TEST(ImageExposure, AutoLetsAtMostOnePercentClip) {
    // 90 dark pixels and 10 very bright ones: the log-average scale would clip 10%.
    std::vector<float> luminances(90, 0.01f);
    luminances.resize(100, 100.0f);
    const Image image = greyImage(luminances);
    const double scale = autoExposureScale(image);
    EXPECT_LT(scale, 0.18 / std::exp(0.9 * std::log(0.01) + 0.1 * std::log(100.0)));
    const Image rgb = xyzToLinearSrgb(image, scale);
    int clipped = 0;
    for (int x = 0; x < rgb.width; ++x) {
        const float* p = rgb.at(x, 0);
        clipped += std::max({p[0], p[1], p[2]}) > 1 + 1e-6 ? 1 : 0;
    }
    EXPECT_LE(clipped, 1);
    EXPECT_NEAR(scale, 0.01, 1e-6);  // the brightest pixels land exactly on 1
}

TEST(ImageExposure, XyzToLinearSrgbAppliesScale) {
    const Image rgb = xyzToLinearSrgb(greyImage({1, 0.25f}), 2.0);
    ASSERT_EQ(rgb.channels, 3);
    EXPECT_EQ(rgb.channelNames, (std::vector<std::string>{"R", "G", "B"}));
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(rgb.at(0, 0)[c], 2.0, 1e-6);
        EXPECT_NEAR(rgb.at(1, 0)[c], 0.5, 1e-6);
    }
}

// IEC 61966-2-1 transfer curve: 0.5 linear encodes to 0.7354, 255 * 0.7354 = 187.5 -> 188.
TEST(ImageExposure, Srgb8KnownValues) {
    Image rgb(2, 2, 3);
    rgb.pixels = {0, 1, 0.5f, -1, 2, 0.0031308f, NAN, 0.18f, 0.25f, 1e-4f, 0.9f, 1e30f};
    const std::vector<uint8_t> bytes = toSrgb8(rgb);
    const std::vector<uint8_t> expected = {0, 255, 188, 0, 255, 10, 0, 118, 137, 0, 243, 255};
    EXPECT_EQ(bytes, expected);
}

// The linear value whose sRGB encoding is `code` / 255 (code may be fractional).
float linearOfCode(double code) {
    return float(srgbDecode(code / 255.0));
}

// A dim ramp from byte 24 to byte 28 over 256 columns (the default render's tall block is such a
// ramp): rounded to nearest it is 5 flat bands, up to half a byte off; dithered, every byte is
// one of the two around its value and the mean of each 8-column block (512 pixels) is the
// block's exact mean within the dither's sampling error (at most 0.5 / sqrt(512) = 0.022 byte,
// so 0.1 is 4.5 sd), and the image is the same every time.
TEST(ImageExposure, DitheredRampKeepsEveryBlocksMeanWithoutBands) {
    const int width = 256, height = 64, block = 8;
    Image rgb(width, height, 3);
    std::vector<double> code(width);
    for (int x = 0; x < width; ++x) {
        code[std::size_t(x)] = 24.0 + 4.0 * x / (width - 1);
        for (int y = 0; y < height; ++y) {
            for (int c = 0; c < 3; ++c)
                rgb.at(x, y)[c] = linearOfCode(code[std::size_t(x)]);
        }
    }
    const std::vector<uint8_t> nearest = toSrgb8(rgb);
    const std::vector<uint8_t> dithered = toSrgb8(rgb, Rounding::Dithered);
    EXPECT_EQ(dithered, toSrgb8(rgb, Rounding::Dithered));  // deterministic
    double worstNearest = 0, worstDithered = 0;
    for (int x0 = 0; x0 < width; x0 += block) {
        double exact = 0, sumNearest = 0, sumDithered = 0;
        for (int x = x0; x < x0 + block; ++x) {
            exact += code[std::size_t(x)] / block;
            for (int y = 0; y < height; ++y) {
                const std::size_t p = 3 * (std::size_t(y) * width + x);
                EXPECT_EQ(dithered[p], dithered[p + 1]);  // one offset for the pixel's channels
                EXPECT_EQ(dithered[p], dithered[p + 2]);
                EXPECT_LE(std::abs(double(dithered[p]) - code[std::size_t(x)]), 1.0 + 1e-4);
                sumNearest += nearest[p];
                sumDithered += dithered[p];
            }
        }
        const double pixels = double(block) * height;
        worstNearest = std::max(worstNearest, std::abs(sumNearest / pixels - exact));
        worstDithered = std::max(worstDithered, std::abs(sumDithered / pixels - exact));
    }
    EXPECT_GT(worstNearest, 0.4);  // the bands
    EXPECT_LT(worstDithered, 0.1);
    // Whole bytes, black and white are not moved.
    Image flat(3, 1, 3);
    flat.pixels = {0, 0, 0, 1, 1, 1, linearOfCode(100), linearOfCode(100), linearOfCode(100)};
    EXPECT_EQ(toSrgb8(flat, Rounding::Dithered),
              (std::vector<uint8_t>{0, 0, 0, 255, 255, 255, 100, 100, 100}));
}

}  // namespace
}  // namespace daisy
