#pragma once
// The colour a linear-sRGB reflectance comes back as on a wavelength set: upsampled (Jakob &
// Hanika 2019), sampled on the set, lit by D65 projected on the same set, turned into XYZ with
// the set's weights (normalised so a perfect white has Y = 1) and then into linear sRGB. This is
// the renderer's path for a diffuse surface under a D65 light, with no white balance; on a good
// set it returns the input. Used by tests and tools/spectral_report.
#include <vector>

#include "spectral/color.h"
#include "spectral/rgb_upsampling.h"
#include "spectral/wavelength_set.h"

namespace daisy {

class ReflectanceRoundTrip {
public:
    // Upsampling with `table` (which must outlive this object): its lookup followed by the
    // Gauss-Newton polish of rgbToReflectance, or the lookup alone when !polish.
    explicit ReflectanceRoundTrip(const WavelengthSet& set,
                                  const RgbToSpectrumTable& table = srgbToSpectrumTable(),
                                  bool polish = true);

    // The reflectance's samples on the set (each in [0, 1]).
    std::vector<double> samples(const Rgb& rgb) const;
    Xyz xyz(const Rgb& rgb) const;
    Rgb operator()(const Rgb& rgb) const { return xyzToLinearSrgb(xyz(rgb)); }

    // XYZ of a perfect white (reflectance 1) on this set: D65's white point as the set sees it.
    Xyz whiteXyz() const;

private:
    WavelengthSet set_;
    const RgbToSpectrumTable& table_;
    bool polish_;
    std::vector<double> illuminant_;
};

}  // namespace daisy
