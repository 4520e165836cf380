#pragma once
// From linear XYZ radiance to display pixels (DESIGN.md sections 4 and 7): exposure (fixed EV or
// automatic from the image's luminance), XYZ -> linear sRGB (IEC 61966-2-1), and 8-bit sRGB.
#include <cstdint>
#include <string>
#include <vector>

#include "core/expected.h"
#include "image/image.h"

namespace daisy {

// "auto" -> nullopt-like automatic; a number -> that EV. Error text for anything else.
struct Exposure {
    bool automatic = true;
    double ev = 0;  // used when !automatic: pixel scale = 2^ev
};
Expected<Exposure> parseExposure(const std::string& text);

// The scale an automatic exposure applies to an XYZ image (channels 0..2): maps the image's
// log-average luminance Y of the hit pixels to 0.18 (Reinhard et al. 2002 "key" of a normal
// scene), limited so that no more than 1% of the pixels clip. 1 for an all-black image.
double autoExposureScale(const Image& xyz);

// The scale for `exposure` on `xyz`: 2^ev, or autoExposureScale.
double exposureScale(const Exposure& exposure, const Image& xyz);

// XYZ (3 channels) -> linear sRGB (3 channels), each value times `scale`. Out-of-gamut values
// are kept (may be negative); the 8-bit conversion clips.
Image xyzToLinearSrgb(const Image& xyz, double scale);

// Linear sRGB (3 channels) -> 8-bit sRGB with the IEC 61966-2-1 transfer curve, clipped to
// [0, 1], rounded to nearest: width * height * 3 bytes.
std::vector<uint8_t> toSrgb8(const Image& linearSrgb);

}  // namespace daisy
