#pragma once
// The committed sRGB -> spectrum coefficient table, in the layout RgbToSpectrumTable documents.
// Defined in rgb_table.cpp, which tools/make_rgb_table generates; use srgbToSpectrumTable().
#include <span>

namespace daisy {

extern const int kSrgbTableResolution;
extern const std::span<const float> kSrgbTableCoefficients;

}  // namespace daisy
