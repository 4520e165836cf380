#pragma once
// Typed descriptions of spectra and fluorescence as a scene file states them (DESIGN.md
// sections 4, 5 and 10). They are parsed and range-checked on load; turning them into sampled
// spectra and re-radiation matrices is the spectral module's job.
#include <array>
#include <string>
#include <variant>
#include <vector>

namespace daisy {

// Linear sRGB triple. As a reflectance each component is in [0, 1] (Jakob & Hanika 2019
// upsampling); as an emission it is non-negative and scales a bounded shape times D65.
struct RgbSpectrum {
    std::array<double, 3> rgb{0, 0, 0};
};

// Piecewise-linear samples: wavelengths strictly ascending, in nm; one value per wavelength.
struct TabulatedSpectrum {
    std::vector<double> wavelengthsNm;
    std::vector<double> values;
};

// A named illuminant: D65, D50, A, F1..F12 or blacklight (canonical spelling, see presets.h).
struct PresetSpectrum {
    std::string name;
};

// Planck's law at temperatureK, normalised to a peak of 1 before the scale.
struct BlackbodySpectrum {
    double temperatureK = 0;
};

// A Gaussian of peak 1 at peakNm with full width at half maximum fwhmNm.
struct GaussianSpectrum {
    double peakNm = 0;
    double fwhmNm = 0;
};

using SpectrumShape = std::variant<RgbSpectrum, TabulatedSpectrum, PresetSpectrum,
                                   BlackbodySpectrum, GaussianSpectrum>;

struct SpectrumSpec {
    SpectrumShape shape;
    double scale = 1.0;  // multiplies the shape; >= 0
};

// A named fluorophore preset (see presets.h).
struct FluorophorePreset {
    std::string name;
};

// Absorption a(l) in [0, 1], emission shape e(l) (any positive scale; renormalised), quantum
// yield Q in [0, 1] (photons out per photon absorbed). DESIGN.md section 5.
struct FluorescenceParams {
    SpectrumSpec absorption;
    SpectrumSpec emission;
    double quantumYield = 1.0;
};

// A measured re-radiation matrix: values[o][i] is the fraction of light at wavelengthsNm[i]
// re-radiated at wavelengthsNm[o] (reflection on the diagonal). Square, non-negative, lower
// triangular in ascending wavelength order, every column sum <= 1.
struct FluorescenceMatrix {
    std::vector<double> wavelengthsNm;
    std::vector<std::vector<double>> values;
};

// The original DaisyRiot MTL convention: `Ks` is the colour a surface fluoresces with under UV.
struct FluorescentColor {
    std::array<double, 3> rgb{0, 0, 0};
};

using FluorescenceSpec =
    std::variant<FluorophorePreset, FluorescenceParams, FluorescenceMatrix, FluorescentColor>;

}  // namespace daisy
