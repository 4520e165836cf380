#pragma once
// What the patch pipeline draws per vertex, from a solver snapshot: CIE XYZ
// radiance for the colour view, and one scalar for false colour (luminance Y, or the radiance at
// one wavelength sample, UV samples included), smooth (the per-corner vertex radiance that
// `daisy render` interpolates) or flat (each patch's own value).
#include <optional>
#include <string>
#include <vector>

#include "core/expected.h"
#include "viewer/solve_worker.h"

namespace daisy::viewer {

enum class DisplayQuantity { Colour, Luminance, Wavelength };

struct DisplaySettings {
    DisplayQuantity quantity = DisplayQuantity::Colour;
    bool smooth = true;  // vertex radiance; false = flat per patch
    std::size_t wavelengthIndex = 0;  // DisplayQuantity::Wavelength: the sample shown
    bool autoRange = true;  // false colour range from the values shown
    double falseLo = -3, falseHi = 0;  // log10 of the range's ends when !autoRange

    bool operator==(const DisplaySettings&) const = default;
};

// log10 of the false-colour ramp's ends.
struct FalseRange {
    double lo = -3;
    double hi = 0;
};

// Fills `values` with 3 x patches vertices of 4 floats: X, Y, Z (radiance, W m^-2 sr^-1
// normalised as Session::patchChannels) and the false-colour scalar (Y, or L at the sample in
// W m^-2 sr^-1 nm^-1). Returns the false-colour range: the settings' own, or with autoRange the
// decade span from the largest scalar down to the smallest positive one, at most 4 decades.
FalseRange displayValues(const DisplaySnapshot& snapshot, const DisplaySettings& settings,
                         std::vector<float>& values);

// `--display LIST`: comma-separated words, each setting one control of the panel's view section:
// colour | luminance | wavelength:NM (the sample nearest NM) | flat | smooth | wireframe.
struct DisplayChoice {
    DisplaySettings settings;
    bool wireframe = false;
    std::optional<double> wavelengthNm;  // resolved by nearestSample
};
Expected<DisplayChoice> parseDisplay(const std::string& text);

// The index of the sample nearest `nm` (the first of two equally near); 0 for an empty list.
std::size_t nearestSample(const std::vector<double>& wavelengthsNm, double nm);

}  // namespace daisy::viewer
