#pragma once
// Colour conversions between CIE XYZ, linear sRGB, encoded sRGB and CIELAB (DESIGN.md section
// 4). XYZ is relative: Y = 1 is the reference white (a perfect diffuser under the illuminant, or
// a flat emission spectrum of value 1, see wavelength_set.h). No white balance is applied
// anywhere unless a caller asks for it with adaptXyzBradford().
#include <array>
#include <cstdint>

namespace daisy {

using Xyz = std::array<double, 3>;
using Rgb = std::array<double, 3>;
using Lab = std::array<double, 3>;
using Matrix3 = std::array<std::array<double, 3>, 3>;

// IEC 61966-2-1:1999 (sRGB): primaries and white point (D65) as CIE 1931 xy.
inline constexpr std::array<double, 2> kSrgbRedXy{0.64, 0.33};
inline constexpr std::array<double, 2> kSrgbGreenXy{0.30, 0.60};
inline constexpr std::array<double, 2> kSrgbBlueXy{0.15, 0.06};
inline constexpr std::array<double, 2> kD65WhiteXy{0.3127, 0.3290};

// The linear-sRGB -> XYZ matrix derived in double precision from the IEC 61966-2-1 primaries
// and white point (the standard prints it rounded to 4 decimals), and its exact inverse.
const Matrix3& linearSrgbToXyzMatrix();
const Matrix3& xyzToLinearSrgbMatrix();
// The same derivation with another white (XYZ, Y = 1): the sRGB primaries balanced so that RGB
// (1, 1, 1) maps to `whiteXyz`.
Matrix3 srgbPrimariesToXyzMatrix(const Xyz& whiteXyz);

Rgb xyzToLinearSrgb(const Xyz& xyz);
Xyz linearSrgbToXyz(const Rgb& rgb);

// The sRGB transfer curve (IEC 61966-2-1 section 5.2): linear [0, 1] -> encoded [0, 1] and back.
// Inputs outside [0, 1] are clamped; this is the 8-bit display encoding, not a tone map.
double srgbEncode(double linear);
double srgbDecode(double encoded);

// Chromaticity (x, y) of an XYZ triple; (0, 0) for black.
std::array<double, 2> xyzToXy(const Xyz& xyz);
// XYZ with luminance Y from chromaticity (x, y), y > 0.
Xyz xyToXyz(const std::array<double, 2>& xy, double luminanceY = 1.0);

// CIE 1976 L*a*b* relative to the reference white `whiteXyz` (CIE 015:2018 section 8.2.1).
Lab xyzToLab(const Xyz& xyz, const Xyz& whiteXyz);
// CIE 1976 colour difference Delta E*ab: the Euclidean distance in L*a*b*.
double deltaE76(const Lab& a, const Lab& b);
// CIEDE2000 colour difference Delta E00 (CIE 142-2001) with k_L = k_C = k_H = 1, implemented
// as in Sharma, Wu & Dalal 2005, "The CIEDE2000 Color-Difference Formula: Implementation Notes,
// Supplementary Test Data, and Mathematical Observations", Color Res. Appl. 30(1), eqs. 1-22.
// Symmetric in its arguments.
double deltaE2000(const Lab& a, const Lab& b);
// An 8-bit encoded sRGB colour (IEC 61966-2-1) as L*a*b* relative to the sRGB white (D65, RGB
// (1, 1, 1)), e.g. for comparing rendered PNG pixels with deltaE2000.
Lab srgb8ToLab(const std::array<uint8_t, 3>& srgb8);

// Von Kries adaptation in the Bradford cone space (Lam 1985, as in CIECAM97s): maps a colour seen
// under `sourceWhite` to the corresponding colour under `targetWhite`. Opt-in white balance, e.g.
// for a scene lit by illuminant A shown on a D65 display.
Xyz adaptXyzBradford(const Xyz& xyz, const Xyz& sourceWhite, const Xyz& targetWhite);

Matrix3 multiply(const Matrix3& a, const Matrix3& b);
std::array<double, 3> multiply(const Matrix3& m, const std::array<double, 3>& v);
// Inverse of a non-singular 3x3 matrix (checked).
Matrix3 inverse(const Matrix3& m);

}  // namespace daisy
