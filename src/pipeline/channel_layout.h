#pragma once
// The per-patch (and per-corner) display channels every image and the viewer read:
//     [L_0 .. L_{m-1} when spectral] X Y Z coverage,
// L = B / pi the radiance of a Lambertian patch (W m^-2 sr^-1 nm^-1) at each wavelength sample,
// X Y Z its CIE 1931 tristimulus values, coverage 1 for a surface (the renderer's box filter
// divides by it). Readers name channels through this layout, never by arithmetic of their own.
#include <cstddef>
#include <span>
#include <vector>

#include "spectral/wavelength_set.h"

namespace daisy {

struct ChannelLayout {
    std::size_t wavelengthCount = 0;  // m
    bool spectral = false;  // the m radiance channels are present

    int count() const { return int(spectral ? wavelengthCount : 0) + 4; }
    // Channel of L at sample k. Precondition: spectral, k < wavelengthCount.
    int radiance(std::size_t k) const { return int(k); }
    int x() const { return int(spectral ? wavelengthCount : 0); }
    int y() const { return x() + 1; }
    int z() const { return x() + 2; }
    int coverage() const { return x() + 3; }
};

// The channels of radiosity `b` (n x m, W m^-2 nm^-1) per patch, row-major, coverage 1.
std::vector<float> radiosityChannels(const WavelengthSet& set, std::span<const double> b,
                                     bool spectral);

}  // namespace daisy
