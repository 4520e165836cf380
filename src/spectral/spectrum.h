#pragma once
// Spectra as functions of wavelength, built from the scene's SpectrumSpec descriptions, and
// their projection onto a WavelengthSet (DESIGN.md section 4).
//
// Units: an emission spectrum is a spectral radiant exitance in W m^-2 nm^-1 (DESIGN.md
// section 2) once multiplied by the scene's scale; reflectance and absorption are fractions.
// Normalisation of the built-in shapes:
// - CIE illuminants (D65, D50, A, F1..F12): luminance-normalised, integral S ybar =
//   integral ybar, so a preset has the luminance (Y = 1) of a flat spectrum of value 1;
// - blackbody, Gaussian and blacklight: peak 1;
// - RGB emission: XYZ equals the linear-sRGB colour's XYZ (Y = luminance of the RGB).
// Sampling on a WavelengthSet depends on the role:
// - emission (power): sample k holds the hat-weighted mean integral s h_k / integral h_k
//   (hats: wavelength_set.h). It conserves spectral power (sum_k s_k * binWidth_k = integral s
//   over the set's domain), so a line between two samples (the 405 nm mercury line, a Gaussian
//   narrower than the spacing) keeps its energy on any set. The one exception is a table that
//   stops short of the domain's ends: the flat parts of the first and last hats (out to 360 and
//   830 nm) stand for wavelengths the set does not resolve, and there both integrals run only
//   over the wavelengths the table covers, so a table ending exactly at the last sample gives it
//   the mean over the table's last interval (the rising half hat), not that diluted by the
//   empty band beyond. A table ending at 700 nm on a set ending at 700 nm then stands for the
//   same spectrum held flat to 830 nm;
// - reflectance and absorption (fractions that multiply the light pointwise): the value at the
//   sample. Averaging them too would blur steep edges twice (once here, once in the hat
//   reconstruction): on the fine set it doubles the RGB round-trip error of saturated colours
//   (measured 2.2e-3 against 1.3e-3, docs/spectral.md).
#include <array>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "core/expected.h"
#include "spectral/rgb_upsampling.h"
#include "spectral/spectrum_spec.h"
#include "spectral/wavelength_set.h"

namespace daisy {

// What a spectrum is used as. Decides how RGB is upsampled (a bounded reflectance, or a shape
// times D65 for emission), how a table continues past its ends (reflectance and absorption
// hold their end values; emission is 0 outside its table) and how it is sampled (above).
enum class SpectrumRole { Reflectance, Emission };

class Spectrum {
public:
    struct Impl;

    Spectrum();  // zero everywhere
    static Spectrum constant(double value);
    // Piecewise linear through (nm[i], values[i]); nm strictly ascending; outside the table the
    // end values (holdEnds) or 0.
    static Spectrum tabulated(std::vector<double> nm, std::vector<double> values, bool holdEnds);
    // height * exp(-(l - peak)^2 / (2 sigma^2)), sigma = fwhm / (2 sqrt(2 ln 2)), summed.
    struct Gaussian {
        double peakNm;
        double fwhmNm;
        double height;
    };
    static Spectrum gaussians(std::vector<Gaussian> terms);
    // Planck's law at temperatureK, divided by its value at the Wien peak (peak 1).
    static Spectrum blackbody(double temperatureK);
    static Spectrum reflectance(const SigmoidPolynomial& shape);
    static Spectrum emission(const RgbEmission& emission);

    Spectrum scaled(double factor) const;
    // This spectrum times l / 560 nm: a power spectrum as a photon-count shape (photons carry
    // energy h c / l), unchanged at 560 nm.
    Spectrum timesWavelength() const;

    double operator()(double nm) const;

    // Wavelengths (ascending) where the spectrum has a kink or a jump: integration splits there.
    std::span<const double> kinksNm() const;
    // Narrowest feature, nm (a Gaussian's FWHM; infinity for tables): bounds integration steps.
    double featureWidthNm() const;
    // The wavelengths where the spectrum has values of its own, nm: a table's first and last
    // wavelengths when it is 0 outside them (holdEnds false), else -inf .. inf.
    std::array<double, 2> definedRangeNm() const;
    // True when the spectrum is linear between kinks (a table or a constant).
    bool isPiecewiseLinear() const;

    // integral of s(l) * w(l) dl over [a, b], w linear from wa at a to wb at b: Simpson's rule on
    // panels split at the kinks, exact for piecewise-linear spectra.
    double integrate(double aNm, double bNm, double wa = 1, double wb = 1) const;

private:
    std::shared_ptr<const Impl> impl_;
    double scale_ = 1;
};

// Planck's spectral radiance, W sr^-1 m^-2 nm^-1, at `nm` and `temperatureK` (CODATA 2018
// constants).
double planckRadianceNm(double nm, double temperatureK);
// Wien's displacement law: the wavelength of peak spectral radiance per unit wavelength, nm,
// b / T with b = 2.897771955e-3 m K (CODATA 2018).
double wienPeakNm(double temperatureK);

// A named illuminant preset (presets.h spelling, case-insensitive): CIE tables luminance-
// normalised as above; "blacklight" a UV-A lamp (see kBlacklightTerms).
Expected<Spectrum> illuminantPreset(std::string_view name);

// The blacklight preset: a Wood's-glass "BLB" tube or 365 nm LED. The main band is the UV-A
// phosphor (europium-doped strontium borate, peak near 365-370 nm, width ~20 nm) and the small
// line is mercury's 404.7 nm line leaking through the filter (the lamp's violet glow); sources in
// docs/materials.md.
inline constexpr std::array<Spectrum::Gaussian, 2> kBlacklightTerms = {
    Spectrum::Gaussian{365.0, 20.0, 1.0}, Spectrum::Gaussian{404.7, 4.0, 0.08}};

// The spectrum a SpectrumSpec describes, used as `role`, times its scale. Refuses what the
// scene parser would refuse (unknown preset, bad table, non-positive temperature or width,
// negative or non-finite scale); the message has no location: callers add it (withContext).
Expected<Spectrum> makeSpectrum(const SpectrumSpec& spec, SpectrumRole role);

// The spectrum on `set`, one value per sample: hat-weighted means for emission, point values
// for reflectance (see the file comment).
std::vector<double> sampleSpectrum(const WavelengthSet& set, const Spectrum& spectrum,
                                   SpectrumRole role);
Expected<std::vector<double>> sampleSpectrum(const WavelengthSet& set, const SpectrumSpec& spec,
                                             SpectrumRole role);

// "UV-emitting" for the `auto` wavelength set: at least kUvPowerFraction of the spectrum's power
// in [200, 830] nm lies below 400 nm (the UV-A/visible border). Measured: blacklight 98%,
// D65 9.6%, D50 5.2% and white RGB emission (shaped like D65) 9.6% count; a red RGB light
// (0.2%), illuminant A (1.0%), a 2700 K blackbody (0.7%) and the F lamps (tabulated from
// 380 nm, under 2.1%) do not.
inline constexpr double kUvPowerFraction = 0.03;
double uvPowerFraction(const Spectrum& emission);
Expected<bool> isUvEmitting(const SpectrumSpec& emission);

}  // namespace daisy
