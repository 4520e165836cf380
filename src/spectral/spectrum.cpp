#include "spectral/spectrum.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/check.h"
#include "core/strings.h"
#include "spectral/cie_tables.h"
#include "spectral/presets.h"

namespace daisy {

struct Spectrum::Impl {
    enum class Kind { Constant, Table, Gaussians, Blackbody, Reflectance, Emission, Photons };
    Kind kind = Kind::Constant;
    double constant = 0;
    std::vector<double> nm, values;  // Table
    bool holdEnds = false;
    std::vector<Gaussian> gaussians;
    double temperatureK = 0, peakRadiance = 1;  // Blackbody
    SigmoidPolynomial shape;  // Reflectance, Emission
    double emissionScale = 0;  // Emission
    std::shared_ptr<const Impl> inner;  // Photons: inner * innerScale * l / 560 nm
    double innerScale = 1;
    std::vector<double> kinks;
    double featureWidthNm = std::numeric_limits<double>::infinity();

    double evaluate(double lambdaNm) const;
};

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Second radiation constant c2 = h c / k and Wien's displacement constant b (CODATA 2018).
constexpr double kC2MetreKelvin = 1.438776877e-2;
constexpr double kWienMetreKelvin = 2.897771955e-3;
// First radiation constant for radiance, c1L = 2 h c^2 (CODATA 2018), W m^2 sr^-1.
constexpr double kC1LWattSquareMetre = 1.191042972e-16;
// Simpson panels are at most this wide, and at most an eighth of the narrowest feature.
constexpr double kMaxPanelNm = 0.5;
constexpr int kUvLowNm = 200, kUvBorderNm = 400, kUvHighNm = 830;
constexpr double kPhotonReferenceNm = 560;

double evaluateTable(const std::vector<double>& nm, const std::vector<double>& values,
                     bool holdEnds, double lambdaNm) {
    if (lambdaNm < nm.front()) return holdEnds ? values.front() : 0;
    if (lambdaNm > nm.back()) return holdEnds ? values.back() : 0;
    const auto upper = std::upper_bound(nm.begin(), nm.end(), lambdaNm);
    if (upper == nm.end()) return values.back();
    const std::size_t i = std::size_t(upper - nm.begin());
    const double t = (lambdaNm - nm[i - 1]) / (nm[i] - nm[i - 1]);
    return values[i - 1] + t * (values[i] - values[i - 1]);
}

// Planck's law up to a constant: lambda^-5 / (exp(c2 / (lambda T)) - 1), lambda in metres.
double planckShape(double lambdaM, double temperatureK) {
    const double denominator = std::expm1(kC2MetreKelvin / (lambdaM * temperatureK));
    if (!std::isfinite(denominator)) return 0;
    return 1.0 / (std::pow(lambdaM, 5) * denominator);
}

const Spectrum& d65() {
    static const Spectrum kD65 = [] {
        auto spectrum = illuminantPreset("D65");
        DAISY_CHECK(spectrum.ok());
        return *spectrum;
    }();
    return kD65;
}

}  // namespace

double Spectrum::Impl::evaluate(double lambdaNm) const {
    switch (kind) {
        case Kind::Constant:
            return constant;
        case Kind::Table:
            return evaluateTable(nm, values, holdEnds, lambdaNm);
        case Kind::Gaussians: {
            double sum = 0;
            for (const Gaussian& g : gaussians) {
                const double sigma = g.fwhmNm / (2 * std::sqrt(2 * std::log(2.0)));
                const double d = (lambdaNm - g.peakNm) / sigma;
                sum += g.height * std::exp(-0.5 * d * d);
            }
            return sum;
        }
        case Kind::Blackbody:
            return planckShape(lambdaNm * 1e-9, temperatureK) / peakRadiance;
        case Kind::Reflectance:
            return shape(lambdaNm);
        case Kind::Emission:
            return emissionScale * shape(lambdaNm) * d65()(lambdaNm);
        case Kind::Photons:
            return innerScale * inner->evaluate(lambdaNm) * lambdaNm / kPhotonReferenceNm;
    }
    return 0;
}

Spectrum::Spectrum() : impl_(std::make_shared<Impl>()) {}

Spectrum Spectrum::constant(double value) {
    Spectrum s;
    auto impl = std::make_shared<Impl>();
    impl->constant = value;
    s.impl_ = impl;
    return s;
}

Spectrum Spectrum::tabulated(std::vector<double> nm, std::vector<double> values, bool holdEnds) {
    DAISY_CHECK(!nm.empty() && nm.size() == values.size());
    Spectrum s;
    auto impl = std::make_shared<Impl>();
    impl->kind = Impl::Kind::Table;
    impl->kinks = nm;
    impl->nm = std::move(nm);
    impl->values = std::move(values);
    impl->holdEnds = holdEnds;
    s.impl_ = impl;
    return s;
}

Spectrum Spectrum::gaussians(std::vector<Gaussian> terms) {
    Spectrum s;
    auto impl = std::make_shared<Impl>();
    impl->kind = Impl::Kind::Gaussians;
    for (const Gaussian& g : terms) {
        DAISY_CHECK(g.fwhmNm > 0);
        impl->featureWidthNm = std::min(impl->featureWidthNm, g.fwhmNm);
    }
    impl->gaussians = std::move(terms);
    s.impl_ = impl;
    return s;
}

Spectrum Spectrum::blackbody(double temperatureK) {
    DAISY_CHECK(temperatureK > 0);
    Spectrum s;
    auto impl = std::make_shared<Impl>();
    impl->kind = Impl::Kind::Blackbody;
    impl->temperatureK = temperatureK;
    impl->peakRadiance = planckShape(kWienMetreKelvin / temperatureK, temperatureK);
    s.impl_ = impl;
    return s;
}

Spectrum Spectrum::reflectance(const SigmoidPolynomial& shape) {
    Spectrum s;
    auto impl = std::make_shared<Impl>();
    impl->kind = Impl::Kind::Reflectance;
    impl->shape = shape;
    impl->kinks = {kSigmoidFirstNm, kSigmoidLastNm};
    s.impl_ = impl;
    return s;
}

Spectrum Spectrum::emission(const RgbEmission& emission) {
    Spectrum s;
    auto impl = std::make_shared<Impl>();
    impl->kind = Impl::Kind::Emission;
    impl->shape = emission.shape;
    impl->emissionScale = emission.scale;
    const auto kinks = d65().kinksNm();
    impl->kinks.assign(kinks.begin(), kinks.end());
    s.impl_ = impl;
    return s;
}

Spectrum Spectrum::scaled(double factor) const {
    Spectrum s = *this;
    s.scale_ *= factor;
    return s;
}

Spectrum Spectrum::timesWavelength() const {
    Spectrum s;
    auto impl = std::make_shared<Impl>();
    impl->kind = Impl::Kind::Photons;
    impl->inner = impl_;
    impl->innerScale = scale_;
    impl->kinks = impl_->kinks;
    impl->featureWidthNm = impl_->featureWidthNm;
    s.impl_ = impl;
    return s;
}

double Spectrum::operator()(double nm) const {
    return scale_ * impl_->evaluate(nm);
}

std::span<const double> Spectrum::kinksNm() const {
    return impl_->kinks;
}

double Spectrum::featureWidthNm() const {
    return impl_->featureWidthNm;
}

std::array<double, 2> Spectrum::definedRangeNm() const {
    const Impl* impl = impl_.get();
    while (impl->kind == Impl::Kind::Photons)
        impl = impl->inner.get();
    if (impl->kind == Impl::Kind::Table && !impl->holdEnds)
        return {impl->nm.front(), impl->nm.back()};
    return {-kInfinity, kInfinity};
}

bool Spectrum::isPiecewiseLinear() const {
    return impl_->kind == Impl::Kind::Constant || impl_->kind == Impl::Kind::Table;
}

double Spectrum::integrate(double aNm, double bNm, double wa, double wb) const {
    if (!(bNm > aNm)) return 0;
    std::vector<double> cuts = {aNm};
    for (double kink : impl_->kinks) {
        if (kink > aNm && kink < bNm) cuts.push_back(kink);
    }
    cuts.push_back(bNm);
    const double panelNm = std::min(kMaxPanelNm, featureWidthNm() / 8);
    const auto weight = [&](double x) { return wa + (wb - wa) * (x - aNm) / (bNm - aNm); };
    double sum = 0;
    for (std::size_t piece = 0; piece + 1 < cuts.size(); ++piece) {
        const double p = cuts[piece], q = cuts[piece + 1];
        const int panels = isPiecewiseLinear() ? 1 : std::max(1, int(std::ceil((q - p) / panelNm)));
        const double h = (q - p) / panels;
        // The spectrum is evaluated a hair inside the piece's ends so that a jump at a kink (a
        // table's end) is seen from the inside; weights and widths use the true ends.
        const double nudge = 1e-11 * (q - p);
        for (int i = 0; i < panels; ++i) {
            const double x0 = p + i * h, x1 = i + 1 == panels ? q : p + (i + 1) * h;
            const double xm = 0.5 * (x0 + x1);
            const double f0 = (*this)(i == 0 ? x0 + nudge : x0);
            const double f1 = (*this)(i + 1 == panels ? x1 - nudge : x1);
            sum += (x1 - x0) / 6 * (f0 * weight(x0) + 4 * (*this)(xm)*weight(xm) + f1 * weight(x1));
        }
    }
    return sum;
}

double planckRadianceNm(double nm, double temperatureK) {
    return kC1LWattSquareMetre * planckShape(nm * 1e-9, temperatureK) * 1e-9;
}

double wienPeakNm(double temperatureK) {
    return kWienMetreKelvin / temperatureK * 1e9;
}

Expected<Spectrum> illuminantPreset(std::string_view name) {
    const auto canonical = canonicalIlluminantPreset(name);
    if (!canonical) {
        return Error{concat("unknown illuminant preset '", name,
                            "'; known: ", joinNames(illuminantPresetNames()))};
    }
    if (*canonical == "blacklight") {
        return Spectrum::gaussians({kBlacklightTerms.begin(), kBlacklightTerms.end()});
    }
    for (const CieIlluminantTable& table : kCieIlluminants) {
        if (table.name != *canonical) continue;
        std::vector<double> nm(table.values.size());
        for (std::size_t k = 0; k < nm.size(); ++k)
            nm[k] = table.firstNm + double(k) * table.stepNm;
        Spectrum raw =
            Spectrum::tabulated(std::move(nm), {table.values.begin(), table.values.end()}, false);
        double luminance = 0;  // sum of S ybar over the 1 nm table, as cieYIntegral()
        for (int i = 0; i < kCieCmfCount; ++i)
            luminance += raw(kCieCmfFirstNm + i) * kCie1931Cmf[i][1];
        return raw.scaled(cieYIntegral() / luminance);
    }
    return Error{concat("illuminant preset '", *canonical, "' has no CIE table")};
}

Expected<Spectrum> makeSpectrum(const SpectrumSpec& spec, SpectrumRole role) {
    if (!std::isfinite(spec.scale) || spec.scale < 0) {
        return Error{concat("scale ", spec.scale, " is not a finite number >= 0")};
    }
    struct Visitor {
        SpectrumRole role;
        Expected<Spectrum> operator()(const RgbSpectrum& rgb) const {
            for (double v : rgb.rgb) {
                if (!std::isfinite(v) || v < 0) {
                    return Error{concat("rgb component ", v, " is not a finite number >= 0")};
                }
            }
            if (role == SpectrumRole::Reflectance) {
                return Spectrum::reflectance(rgbToReflectance(rgb.rgb));
            }
            return Spectrum::emission(rgbToEmission(rgb.rgb));
        }
        Expected<Spectrum> operator()(const TabulatedSpectrum& table) const {
            if (table.wavelengthsNm.empty() || table.wavelengthsNm.size() != table.values.size()) {
                return Error{concat("table has ", table.wavelengthsNm.size(), " wavelengths and ",
                                    table.values.size(), " values; give one value per wavelength")};
            }
            for (std::size_t i = 0; i < table.values.size(); ++i) {
                const double nm = table.wavelengthsNm[i];
                if (!std::isfinite(nm) || (i > 0 && nm <= table.wavelengthsNm[i - 1])) {
                    return Error{
                        concat("table wavelength ", nm, " nm is not finite and ascending")};
                }
                if (!std::isfinite(table.values[i])) {
                    return Error{concat("table value at ", nm, " nm is not finite")};
                }
            }
            return Spectrum::tabulated(table.wavelengthsNm, table.values,
                                       role == SpectrumRole::Reflectance);
        }
        Expected<Spectrum> operator()(const PresetSpectrum& preset) const {
            return illuminantPreset(preset.name);
        }
        Expected<Spectrum> operator()(const BlackbodySpectrum& blackbody) const {
            if (!std::isfinite(blackbody.temperatureK) || blackbody.temperatureK <= 0) {
                return Error{
                    concat("blackbody temperature ", blackbody.temperatureK, " K is not positive")};
            }
            return Spectrum::blackbody(blackbody.temperatureK);
        }
        Expected<Spectrum> operator()(const GaussianSpectrum& gaussian) const {
            if (!std::isfinite(gaussian.peakNm) || !std::isfinite(gaussian.fwhmNm) ||
                gaussian.fwhmNm <= 0) {
                return Error{concat("gaussian peak ", gaussian.peakNm, " nm, fwhm ",
                                    gaussian.fwhmNm, " nm: needs a finite peak and fwhm > 0")};
            }
            return Spectrum::gaussians({{gaussian.peakNm, gaussian.fwhmNm, 1.0}});
        }
    };
    auto shape = std::visit(Visitor{role}, spec.shape);
    if (!shape) return shape.error();
    return shape->scaled(spec.scale);
}

std::vector<double> sampleSpectrum(const WavelengthSet& set, const Spectrum& spectrum,
                                   SpectrumRole role) {
    std::vector<double> samples(set.size());
    if (role == SpectrumRole::Reflectance) {
        for (std::size_t k = 0; k < set.size(); ++k)
            samples[k] = spectrum(set.wavelengthNm(k));
        return samples;
    }
    const std::size_t last = set.size() - 1;
    // Named variables, not a structured binding: the lambda below captures them, which clang 14
    // (the fuzz build's compiler) refuses for bindings.
    const std::array<double, 2> definedNm = spectrum.definedRangeNm();
    const double definedFromNm = definedNm[0], definedToNm = definedNm[1];
    for (std::size_t k = 0; k < set.size(); ++k) {
        const auto [first, end] = set.hatSupportNm(k);
        const double lk = set.wavelengthNm(k);
        // One half of the hat, from lk to `edge`: falling to 0 at a neighbouring sample, or
        // flat out to the domain's end beyond the first and last samples, where only the part
        // the spectrum defines counts (file comment). Adds its weight to `width`.
        double width = 0;
        const auto half = [&](double edge, bool flat) {
            const double a = std::min(lk, edge), b = std::max(lk, edge);
            if (!flat) {
                width += (b - a) / 2;
                return edge < lk ? spectrum.integrate(a, b, 0, 1) : spectrum.integrate(a, b, 1, 0);
            }
            const double from = std::clamp(definedFromNm, a, b), to = std::clamp(definedToNm, a, b);
            width += to - from;
            return spectrum.integrate(from, to);
        };
        const double left = half(first, k == 0);
        const double right = half(end, k == last);
        samples[k] = width > 0 ? (left + right) / width : spectrum(lk);
    }
    return samples;
}

Expected<std::vector<double>> sampleSpectrum(const WavelengthSet& set, const SpectrumSpec& spec,
                                             SpectrumRole role) {
    auto spectrum = makeSpectrum(spec, role);
    if (!spectrum) return spectrum.error();
    return sampleSpectrum(set, *spectrum, role);
}

double uvPowerFraction(const Spectrum& emission) {
    const double uv = emission.integrate(kUvLowNm, kUvBorderNm);
    const double total = uv + emission.integrate(kUvBorderNm, kUvHighNm);
    return total > 0 ? uv / total : 0;
}

Expected<bool> isUvEmitting(const SpectrumSpec& emission) {
    auto spectrum = makeSpectrum(emission, SpectrumRole::Emission);
    if (!spectrum) return spectrum.error();
    return uvPowerFraction(*spectrum) >= kUvPowerFraction;
}

}  // namespace daisy
