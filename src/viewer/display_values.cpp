#include "viewer/display_values.h"

#include <algorithm>
#include <cmath>

namespace daisy::viewer {

FalseRange displayValues(const DisplaySnapshot& snapshot, const DisplaySettings& settings,
                         std::vector<float>& values) {
    const std::size_t m = snapshot.wavelengthCount;
    const std::size_t channels = m + 4;  // L_0 .. L_{m-1}, X, Y, Z, coverage
    const std::size_t patchCount = snapshot.patchValues.size() / channels;
    const std::size_t scalarChannel = settings.quantity == DisplayQuantity::Wavelength
        ? std::min(settings.wavelengthIndex, m - 1)
        : m + 1;
    values.assign(patchCount * 3 * 4, 0.0f);
    float largest = 0, smallest = INFINITY;
    for (std::size_t p = 0; p < patchCount; ++p) {
        for (std::size_t corner = 0; corner < 3; ++corner) {
            const float* source = settings.smooth
                ? snapshot.corners.data() + (p * 3 + corner) * channels
                : snapshot.patchValues.data() + p * channels;
            float* out = values.data() + (p * 3 + corner) * 4;
            out[0] = source[m];
            out[1] = source[m + 1];
            out[2] = source[m + 2];
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

}  // namespace daisy::viewer
