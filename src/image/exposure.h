#pragma once
// From linear XYZ radiance to display pixels (DESIGN.md sections 4 and 7): exposure (fixed EV or
// automatic from the image's luminance), XYZ -> linear sRGB (IEC 61966-2-1), and 8-bit sRGB.
#include <cstdint>
#include <string>
#include <vector>

#include "core/expected.h"
#include "image/image.h"

namespace daisy {

// An exposure setting: automatic, or a fixed number of stops.
struct Exposure {
    bool automatic = true;
    double ev = 0;  // used when !automatic: pixel scale = 2^ev
};
// "auto" (any case) -> automatic; a finite number (e.g. "-1.5") -> that EV. An error naming the
// text for anything else.
Expected<Exposure> parseExposure(const std::string& text);

// The scale an automatic exposure applies to an XYZ image (channels 0..2): maps the image's
// log-average luminance exp(mean(log Y)) to 0.18 (the "key" of a normal scene, Reinhard et al.
// 2002, eq. 1-2), limited so that no more than 1% of those pixels clip (largest linear sRGB
// component times the scale above 1). Only pixels with Y > 0 count: background (misses render
// Y = 0 exactly) and black surfaces would otherwise drag the average to zero. 1 when no pixel
// has Y > 0.
double autoExposureScale(const Image& xyz);

// The scale for `exposure` on `xyz`: 2^ev, or autoExposureScale.
double exposureScale(const Exposure& exposure, const Image& xyz);

// XYZ (channels 0..2) -> linear sRGB (3 channels named R, G, B), each value times `scale`, with
// the IEC 61966-2-1 matrix (spectral/color.h). Out-of-gamut values are kept (may be negative);
// the 8-bit conversion clips.
Image xyzToLinearSrgb(const Image& xyz, double scale);

// How toSrgb8 rounds. `Nearest`: each value to the nearest byte (what comparisons of images
// measure). `Dithered`: each pixel's encoded values (in units of one byte) plus one offset in
// (-1/2, 1/2) from a hash of the pixel's position, the same for its three channels, then to the
// nearest byte: a smooth gradient spanning a few bytes (a dim wall) no longer shows the steps
// of 8 bits as bands, the mean of any area is kept, values that are whole bytes (black, white,
// a flat colour that lands on a byte) are unchanged, and the same image always gives the same
// bytes. For image files people look at.
enum class Rounding { Nearest, Dithered };

// Linear sRGB (3 channels) -> 8-bit sRGB with the IEC 61966-2-1 transfer curve, clipped to
// [0, 1], rounded as `rounding` says: width * height * 3 bytes.
std::vector<uint8_t> toSrgb8(const Image& linearSrgb, Rounding rounding = Rounding::Nearest);

}  // namespace daisy
