#pragma once
// The wavelength samples a solve runs on, with their reconstruction basis and the m x 3 matrix
// that turns sampled spectra into CIE XYZ (DESIGN.md section 4).
//
// Reconstruction: a spectrum known at samples l_0 < ... < l_{m-1} is the piecewise-linear
// function sum_k s_k h_k(l), h_k the "hat" that is 1 at l_k and falls linearly to 0 at l_{k-1}
// and l_{k+1}. At the ends the hats are held flat out to the set's domain
// [min(l_0, 360), max(l_{m-1}, 830)] nm (the CIE 1931 table's range): the outermost samples
// stand for everything between them and the end of the visible range, so a set like meyer4
// (456.4..631.4 nm) still sees the whole colour-matching functions. sum_k h_k = 1 on the domain;
// power outside the domain (e.g. UV below a set's first sample) is not represented.
#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "core/expected.h"
#include "spectral/color.h"
#include "spectral/wavelength_spec.h"

namespace daisy {

class WavelengthSet {
public:
    // Strictly ascending wavelengths in [kMinWavelengthNm, kMaxWavelengthNm], at least one.
    // `name` is for messages and reports ("daisyriot", "400:700:20", ...).
    static Expected<WavelengthSet> fromWavelengths(std::vector<double> wavelengthsNm,
                                                   std::string name);

    std::size_t size() const { return wavelengthsNm_.size(); }
    const std::string& name() const { return name_; }
    double wavelengthNm(std::size_t k) const { return wavelengthsNm_[k]; }
    const std::vector<double>& wavelengthsNm() const { return wavelengthsNm_; }

    // The domain the hats cover, in nm.
    double domainStartNm() const { return domainStartNm_; }
    double domainEndNm() const { return domainEndNm_; }

    // h_k(nm): the reconstruction basis function of sample k (0 outside the domain).
    double hat(std::size_t k, double nm) const;
    // The hat's support [first, last] in nm: the neighbouring samples, or the domain's end.
    std::array<double, 2> hatSupportNm(std::size_t k) const;
    // integral of h_k in nm: the width of spectrum that sample k stands for. Spectral power in
    // a sampled spectral density s is sum_k s_k * binWidthNm(k).
    double binWidthNm(std::size_t k) const { return binWidthsNm_[k]; }
    const std::vector<double>& binWidthsNm() const { return binWidthsNm_; }

    // Row k of the m x 3 spectrum-to-XYZ matrix: integral of h_k(l) {xbar, ybar, zbar}(l) dl
    // over the 1 nm CIE 1931 table, divided by integral of ybar dl (cieYIntegral()), so a flat
    // spectrum of value 1 has Y = 1.
    const std::array<double, 3>& xyzWeights(std::size_t k) const { return xyzWeights_[k]; }

    // XYZ of a sampled spectrum (one value per sample): sum_k values[k] * xyzWeights(k).
    Xyz toXyz(std::span<const double> values) const;
    // XYZ of a reflectance under an illuminant, both sampled on this set, normalised so that a
    // perfect white reflector has Y = 1 (CIE 015:2018 section 7.1, k = 1 / sum S ybar).
    Xyz reflectanceToXyz(std::span<const double> reflectance,
                         std::span<const double> illuminant) const;

private:
    std::string name_;
    std::vector<double> wavelengthsNm_;
    std::vector<double> binWidthsNm_;
    std::vector<std::array<double, 3>> xyzWeights_;
    double domainStartNm_ = 0, domainEndNm_ = 0;
};

// The sum of ybar over the 1 nm CIE 1931 table (1 nm spacing): 106.856917 nm.
double cieYIntegral();

// Presets (DESIGN.md section 4).
// daisyriot: 350..650 nm step 50, the original DaisyRiot's 7 samples.
// meyer4: 456.4, 490.9, 557.7, 631.4 nm (Meyer 1988, "Wavelength selection for synthetic image
//   generation", CVGIP 41: the 4-point Gaussian-quadrature-like choice for colour).
// visible: 400..700 nm step 20 (16 samples).
// auto (the default): 400..700 nm step 10 (31 samples), named "400:700:10": the cheapest density
//   whose images stay within a just-noticeable difference of the fine set's on the demo scenes
//   (`daisy bench`, docs/performance.md); visible's 20 nm is not (mean CIEDE2000 1.05 on the
//   black-light box).
// fine: 360..830 nm step 5 (95 samples), the reference: the CIE tables' own range at the CIE
//   015:2018 recommended 5 nm interval.
WavelengthSet daisyriotWavelengths();
WavelengthSet meyer4Wavelengths();
WavelengthSet visibleWavelengths();
WavelengthSet autoWavelengths();
WavelengthSet fineWavelengths();

// UV excitation samples presets and ranges may add, nm: they cover UV-A (315-400 nm), where black
// lights emit and optical brighteners absorb.
inline constexpr std::array<double, 4> kUvExcitationNm = {320, 340, 360, 380};

// The UV rule: `base` plus the kUvExcitationNm samples that lie more than 10 nm below its
// first sample, only when the scene has both UV-emitting lights (see isUvEmitting in
// spectrum.h) and fluorescent materials; otherwise `base` unchanged. The caller decides the two
// facts; this module does not look at scenes.
WavelengthSet withUvExcitation(const WavelengthSet& base, bool sceneHasUvLights,
                               bool sceneHasFluorescence);

// The set a --wavelengths value names. Presets and ranges pass through withUvExcitation with the
// two scene facts, so a black-light scene keeps its fluorescence at any sample density; an
// explicit list is used exactly as given.
Expected<WavelengthSet> makeWavelengthSet(const WavelengthSpec& spec, bool sceneHasUvLights = false,
                                          bool sceneHasFluorescence = false);

}  // namespace daisy
