#include "viewer/display_values.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/strings.h"

namespace daisy::viewer {

FalseRange displayValues(const DisplaySnapshot& snapshot, const DisplaySettings& settings,
                         std::vector<float>& values) {
    const std::size_t m = snapshot.wavelengthCount;
    const ChannelLayout& layout = snapshot.layout;
    const std::size_t channels = std::size_t(layout.count());
    const std::size_t patchCount = snapshot.patchValues.size() / channels;
    const std::size_t scalarChannel = settings.quantity == DisplayQuantity::Wavelength
        ? std::size_t(layout.radiance(std::min(settings.wavelengthIndex, m - 1)))
        : std::size_t(layout.y());
    values.assign(patchCount * 3 * 4, 0.0f);
    float largest = 0, smallest = INFINITY;
    for (std::size_t p = 0; p < patchCount; ++p) {
        for (std::size_t corner = 0; corner < 3; ++corner) {
            const float* source = settings.smooth
                ? snapshot.corners.data() + (p * 3 + corner) * channels
                : snapshot.patchValues.data() + p * channels;
            float* out = values.data() + (p * 3 + corner) * 4;
            out[0] = source[layout.x()];
            out[1] = source[layout.y()];
            out[2] = source[layout.z()];
            out[3] = source[scalarChannel];
            if (out[3] > 0 && std::isfinite(out[3])) {
                largest = std::max(largest, out[3]);
                smallest = std::min(smallest, out[3]);
            }
        }
    }
    if (!settings.autoRange) return FalseRange{settings.falseLo, settings.falseHi};
    if (!(largest > 0)) return FalseRange{-1, 0};
    FalseRange range;
    range.hi = std::log10(double(largest));
    range.lo = std::max(std::log10(double(smallest)), range.hi - 4);
    if (range.hi - range.lo < 1e-3) range.lo = range.hi - 1;
    return range;
}

Expected<DisplayChoice> parseDisplay(const std::string& text) {
    DisplayChoice choice;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string word = text.substr(start, comma - start);
        start = comma + 1;
        if (word == "colour" || word == "color") {
            choice.settings.quantity = DisplayQuantity::Colour;
        } else if (word == "luminance") {
            choice.settings.quantity = DisplayQuantity::Luminance;
        } else if (word == "flat") {
            choice.settings.smooth = false;
        } else if (word == "smooth") {
            choice.settings.smooth = true;
        } else if (word == "wireframe") {
            choice.wireframe = true;
        } else if (word.rfind("wavelength:", 0) == 0) {
            const std::string number = word.substr(11);
            char* end = nullptr;
            const double nm = std::strtod(number.c_str(), &end);
            if (number.empty() || *end != '\0' || !std::isfinite(nm) || nm <= 0) {
                return Error{concat("--display: '", word, "' is not wavelength:NM")};
            }
            choice.settings.quantity = DisplayQuantity::Wavelength;
            choice.wavelengthNm = nm;
        } else {
            return Error{concat("--display: '", word,
                                "' is not one of colour, luminance, wavelength:NM, flat, smooth, "
                                "wireframe")};
        }
    }
    return choice;
}

std::size_t nearestSample(const std::vector<double>& wavelengthsNm, double nm) {
    std::size_t best = 0;
    for (std::size_t k = 1; k < wavelengthsNm.size(); ++k) {
        if (std::abs(wavelengthsNm[k] - nm) < std::abs(wavelengthsNm[best] - nm)) best = k;
    }
    return best;
}

}  // namespace daisy::viewer
