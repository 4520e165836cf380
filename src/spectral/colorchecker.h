#pragma once
// Test colours for the spectral reports and tests: the 24 patches of the ColorChecker Classic as
// 8-bit sRGB, and a reproducible stream of random linear-sRGB colours.
#include <array>
#include <cstdint>
#include <string_view>

#include "spectral/color.h"

namespace daisy {

struct ColorCheckerPatch {
    std::string_view name;
    std::array<int, 3> srgb8;  // encoded sRGB, 0..255
};

// The widely used sRGB rendition of the 24 ColorChecker Classic patches (D65), e.g. as listed by
// BabelColor (D. Pascale, "RGB coordinates of the Macbeth ColorChecker", 2006) and X-Rite.
// "ColorChecker-like": values as commonly published, rounded to 8 bits.
extern const std::array<ColorCheckerPatch, 24> kColorChecker;

// A patch's linear sRGB (the transfer curve undone).
Rgb colorCheckerLinear(const ColorCheckerPatch& patch);

// SplitMix64 (Steele, Lea & Flood 2014): a tiny reproducible generator, identical on every
// platform (unlike std::uniform_real_distribution), for random test colours.
class SplitMix64 {
public:
    explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next();
    // Uniform in [0, 1) with 53 random bits.
    double uniform() { return double(next() >> 11) * 0x1.0p-53; }

private:
    std::uint64_t state_;
};

}  // namespace daisy
