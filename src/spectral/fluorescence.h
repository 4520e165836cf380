#pragma once
// Fluorescence: the per-material re-radiation matrix M of DESIGN.md section 5 on a wavelength
// set, its validation, and the fluorophore presets.
//
// In the radiosity equation B_i[o] = E_i[o] + sum_i' M[o][i'] G_i[i'] (G the gathered
// irradiance), B and G are spectral densities (W m^-2 nm^-1) at the set's samples. With Q the
// quantum yield, a the fluorophore's absorption, rho the reflectance and e the emission shape,
// all sampled on the set (spectrum.h), and w_k the samples' bin widths (wavelength_set.h):
//     M[o][i] = rho_i delta(o, i) + Q a_i (l_i / l_o) p_i(o) (w_i / w_o),   l_o > l_i,
//     p_i(o)  = e_o w_o / sum_{o' > i} e_o' w_o'
// p_i is the emission restricted to wavelengths above l_i and renormalised to a probability
// (DESIGN.md's e_i), l_i / l_o the Stokes energy loss per photon, and w_i / w_o turns the power
// moved from bin i to bin o into a density (1 on evenly spaced sets, where this is DESIGN.md's
// formula as written). Energy: the power leaving per unit power arriving at l_i is the
// weighted column sum  c_i = sum_o M[o][i] w_o / w_i = rho_i + Q a_i sum_o p_i(o) l_i / l_o,
// at most rho_i + a_i <= 1. Photons: with rho = 0, a = 1, Q = 1, sum_o M[o][i] (w_o / w_i)
// (l_o / l_i) = 1 exactly. Absorbed light at a sample with no emission above it is lost.
#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "core/expected.h"
#include "spectral/color.h"
#include "spectral/spectrum.h"
#include "spectral/spectrum_spec.h"
#include "spectral/wavelength_set.h"

namespace daisy {

// m x m, row-major: values[o * size + i] = M[o][i], density to density (see above).
struct ReradiationMatrix {
    std::size_t size = 0;
    std::vector<double> values;

    double operator()(std::size_t o, std::size_t i) const { return values[o * size + i]; }
    double& operator()(std::size_t o, std::size_t i) { return values[o * size + i]; }
    // True when every off-diagonal entry is 0: M = diag(rho), no fluorescence.
    bool isDiagonal() const;
    // c_i above: power out per unit power in at sample i.
    double powerColumnSum(const WavelengthSet& set, std::size_t i) const;
};

// Slack on "column sums <= 1" and "rho + a <= 1", for rounding.
inline constexpr double kEnergyTolerance = 1e-9;

// Checks M on `set`: size m x m, entries finite and >= 0, zero above the diagonal (light only
// moves to longer wavelengths), every weighted column sum c_i <= 1. The message starts with
// `where` (the material) and names the failing wavelength(s).
Expected<void> validateReradiationMatrix(const WavelengthSet& set, const ReradiationMatrix& m,
                                         std::string_view where);

// Checks a measured matrix on its own wavelengths (a FluorescenceMatrix, values in power
// fractions): at least one wavelength, strictly ascending, square, finite, >= 0, lower
// triangular, plain column sums <= 1.
Expected<void> validateFluorescenceMatrix(const FluorescenceMatrix& matrix, std::string_view where);

// M from sampled reflectance, absorption and emission (one value per sample of `set`) and a
// quantum yield, by the formula above. Refuses rho or a outside [0, 1], rho + a > 1, Q outside
// [0, 1], a negative or all-zero emission, naming `where` and the wavelength.
Expected<ReradiationMatrix> reradiationMatrix(const WavelengthSet& set,
                                              std::span<const double> reflectance,
                                              std::span<const double> absorption,
                                              std::span<const double> emission, double quantumYield,
                                              std::string_view where);

// A measured matrix moved onto `set`. Validated on its own grid first. For each sample l of
// the set: the reflectance is the diagonal interpolated linearly at l (end values held); the
// re-radiated fractions are the columns interpolated linearly in input wavelength (zero outside
// the matrix's range); each output fraction at matrix wavelength g goes to the two set samples
// around g in proportion to their hats, and the part that lands on l's own sample joins the
// diagonal (re-emission within the sample's bin). Exact when the set's wavelengths are the
// matrix's. Validated again on the set.
Expected<ReradiationMatrix> resampleFluorescenceMatrix(const WavelengthSet& set,
                                                       const FluorescenceMatrix& matrix,
                                                       std::string_view where);

// The preset fluorophores (presets.h names, case-insensitive) as absorption (a Gaussian scaled
// to its peak absorption), emission (a Gaussian) and quantum yield. Peaks, widths and yields
// and their sources: docs/materials.md.
struct FluorophoreData {
    std::string_view name;
    double absorptionPeakNm, absorptionFwhmNm, peakAbsorption;
    double emissionPeakNm, emissionFwhmNm;
    double quantumYield;
};
std::span<const FluorophoreData> fluorophoreData();
Expected<FluorescenceParams> fluorophorePresetParams(std::string_view name);

// A fluorophore as spectra: absorption a(l), a fraction; emission e(l), the distribution of the
// emitted photons over wavelength (any scale: DESIGN.md's e, renormalised above each
// excitation wavelength); quantum yield Q in [0, 1].
struct Fluorophore {
    Spectrum absorption;
    Spectrum emission;
    double quantumYield = 1;
};
// From the scene's parameters; the messages say which spectrum is wrong.
Expected<Fluorophore> makeFluorophore(const FluorescenceParams& params);

// The original DaisyRiot MTL convention (`Ks` = the colour a surface fluoresces with under UV)
// as a fluorophore: absorption kFluorescentColorAbsorption from 300 to 400 nm (held below),
// falling linearly to 0 at 420 nm (UV-A and the violet edge, where black lights emit);
// emission the photons of the RGB emission spectrum of Ks / max(Ks) (bounded shape x D65,
// rgb_upsampling.h), so the re-emitted power has the colour of Ks; quantum yield max(Ks), so a
// darker Ks glows less. docs/materials.md.
inline constexpr double kFluorescentColorAbsorption = 0.8;
Fluorophore fluorescentColorFluorophore(const FluorescentColor& color);

// The re-radiation matrix of a material on `set` (DESIGN.md section 5). The reflectance is
// `reflectance` if given, else `baseColor` (linear sRGB, upsampled). Without fluorescence,
// M = diag(rho). With explicit FluorescenceParams, rho and a are used as given and must satisfy
// rho + a <= 1. With a preset or a FluorescentColor the fluorophore is a layer over the
// material's colour: the light it does not absorb meets the base reflectance, so
// rho_effective = rho (1 - a). An explicit matrix replaces everything (the reflectance is its
// diagonal). Errors start with `where`, e.g. Material::origin, and name the wavelength.
Expected<ReradiationMatrix> materialReradiationMatrix(
    const WavelengthSet& set, const std::optional<SpectrumSpec>& reflectance, const Rgb& baseColor,
    const std::optional<FluorescenceSpec>& fluorescence, std::string_view where);

// The emission of a material on `set`: `emission` if given, else the RGB emission of
// `emissiveRgb` (zero for black). W m^-2 nm^-1 per unit of the scene's scale.
Expected<std::vector<double>> materialEmission(const WavelengthSet& set,
                                               const std::optional<SpectrumSpec>& emission,
                                               const Rgb& emissiveRgb, std::string_view where);

}  // namespace daisy
