#include "image/exposure.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

#include "core/check.h"
#include "core/strings.h"
#include "shared/rng.h"
#include "spectral/color.h"

namespace daisy {

namespace {

constexpr double kMiddleGrey = 0.18;  // Reinhard et al. 2002, the key of a normal-key scene
constexpr double kClipFraction = 0.01;

}  // namespace

Expected<Exposure> parseExposure(const std::string& text) {
    if (toLower(text) == "auto") return Exposure{};
    const char* begin = text.c_str();
    char* end = nullptr;
    const double ev = std::strtod(begin, &end);
    // strtod would skip leading white space; a number must be the whole text.
    if (text.empty() || std::isspace(static_cast<unsigned char>(text[0])) ||
        end != begin + text.size() || !std::isfinite(ev)) {
        return Error{concat("exposure \"", text,
                            "\": expected \"auto\" or a number of stops (EV), e.g. -1.5")};
    }
    return Exposure{false, ev};
}

double autoExposureScale(const Image& xyz) {
    DAISY_CHECK(xyz.channels >= 3);
    double logSum = 0;
    std::vector<double> brightest;  // largest linear sRGB component per counted pixel
    brightest.reserve(std::size_t(xyz.width) * xyz.height);
    for (int y = 0; y < xyz.height; ++y) {
        for (int x = 0; x < xyz.width; ++x) {
            const float* p = xyz.at(x, y);
            if (!(p[1] > 0) || !std::isfinite(p[1])) continue;
            logSum += std::log(double(p[1]));
            const Rgb rgb = daisy::xyzToLinearSrgb(Xyz{p[0], p[1], p[2]});
            brightest.push_back(std::max({rgb[0], rgb[1], rgb[2]}));
        }
    }
    if (brightest.empty()) return 1;
    const double logAverage = std::exp(logSum / double(brightest.size()));
    double scale = kMiddleGrey / logAverage;
    // At most floor(1% of n) pixels may exceed 1 after scaling: the brightest value not among
    // them must map to at most 1.
    const std::size_t allowed = std::size_t(kClipFraction * double(brightest.size()));
    const auto limit = brightest.end() - 1 - std::ptrdiff_t(allowed);
    std::nth_element(brightest.begin(), limit, brightest.end());
    if (*limit > 0 && std::isfinite(*limit)) scale = std::min(scale, 1 / *limit);
    return scale;
}

double exposureScale(const Exposure& exposure, const Image& xyz) {
    return exposure.automatic ? autoExposureScale(xyz) : std::exp2(exposure.ev);
}

Image xyzToLinearSrgb(const Image& xyz, double scale) {
    DAISY_CHECK(xyz.channels >= 3);
    const Matrix3& m = xyzToLinearSrgbMatrix();
    Image rgb(xyz.width, xyz.height, 3);
    rgb.channelNames = {"R", "G", "B"};
    for (int y = 0; y < xyz.height; ++y) {
        for (int x = 0; x < xyz.width; ++x) {
            const float* in = xyz.at(x, y);
            float* out = rgb.at(x, y);
            for (int r = 0; r < 3; ++r)
                out[r] = static_cast<float>(scale *
                                            (m[r][0] * in[0] + m[r][1] * in[1] + m[r][2] * in[2]));
        }
    }
    return rgb;
}

std::vector<uint8_t> toSrgb8(const Image& linearSrgb, Rounding rounding) {
    DAISY_CHECK(linearSrgb.channels == 3);
    std::vector<uint8_t> bytes(linearSrgb.pixels.size());
    for (std::size_t pixel = 0; pixel < bytes.size() / 3; ++pixel) {
        // (h + 1/2) / 2^32 - 1/2 lies strictly inside (-1/2, 1/2): a whole byte k stays k.
        const double offset = rounding == Rounding::Dithered
            ? (double(shared::pcgHash(uint32_t(pixel) ^ 0x9e3779b9u)) + 0.5) * 0x1p-32 - 0.5
            : 0.0;
        for (std::size_t c = 0; c < 3; ++c) {
            const double v = linearSrgb.pixels[3 * pixel + c];
            const double encoded = std::isnan(v) ? 0.0 : srgbEncode(v);  // srgbEncode clamps
            bytes[3 * pixel + c] =
                static_cast<uint8_t>(std::clamp(std::lround(encoded * 255 + offset), 0L, 255L));
        }
    }
    return bytes;
}

}  // namespace daisy
