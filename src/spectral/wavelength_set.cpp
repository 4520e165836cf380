#include "spectral/wavelength_set.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "core/strings.h"
#include "spectral/cie_tables.h"

namespace daisy {
namespace {

// UV samples closer than this to the base set's first sample are not added.
constexpr double kUvGapNm = 10.0;

std::vector<double> rangeNm(double startNm, double endNm, double stepNm) {
    std::vector<double> nm;
    // Each sample is start + k * step (no accumulated rounding); the end is inclusive when the
    // step lands on it to within a millionth of a step.
    for (std::size_t k = 0;; ++k) {
        const double value = startNm + double(k) * stepNm;
        if (value > endNm + 1e-6 * stepNm) break;
        nm.push_back(std::min(value, endNm));
    }
    return nm;
}

WavelengthSet mustBuild(std::vector<double> nm, std::string name) {
    auto set = WavelengthSet::fromWavelengths(std::move(nm), std::move(name));
    DAISY_CHECK(set.ok());
    return std::move(*set);
}

}  // namespace

double cieYIntegral() {
    static const double kIntegral = [] {
        double sum = 0;
        for (const auto& row : kCie1931Cmf)
            sum += row[1];
        return sum;
    }();
    return kIntegral;
}

Expected<WavelengthSet> WavelengthSet::fromWavelengths(std::vector<double> wavelengthsNm,
                                                       std::string name) {
    if (wavelengthsNm.empty()) return Error{concat("wavelength set '", name, "' is empty")};
    for (std::size_t k = 0; k < wavelengthsNm.size(); ++k) {
        const double nm = wavelengthsNm[k];
        if (!std::isfinite(nm) || nm < kMinWavelengthNm || nm > kMaxWavelengthNm) {
            return Error{concat("wavelength set '", name, "': ", nm, " nm is outside [",
                                kMinWavelengthNm, ", ", kMaxWavelengthNm, "] nm")};
        }
        if (k > 0 && nm <= wavelengthsNm[k - 1]) {
            return Error{concat("wavelength set '", name, "': ", nm, " nm does not follow ",
                                wavelengthsNm[k - 1],
                                " nm; wavelengths must be strictly ascending")};
        }
    }
    WavelengthSet set;
    set.name_ = std::move(name);
    set.wavelengthsNm_ = std::move(wavelengthsNm);
    set.domainStartNm_ = std::min(set.wavelengthsNm_.front(), double(kCieCmfFirstNm));
    set.domainEndNm_ = std::max(set.wavelengthsNm_.back(), double(kCieCmfLastNm));

    const std::size_t m = set.size();
    set.binWidthsNm_.resize(m);
    for (std::size_t k = 0; k < m; ++k) {
        const double lk = set.wavelengthsNm_[k];
        const double left = k == 0 ? lk - set.domainStartNm_ : (lk - set.wavelengthsNm_[k - 1]) / 2;
        const double right =
            k + 1 == m ? set.domainEndNm_ - lk : (set.wavelengthsNm_[k + 1] - lk) / 2;
        set.binWidthsNm_[k] = left + right;
    }

    // Integrate each hat against the colour-matching functions by the CIE's own rule: a sum
    // over the 1 nm table (CIE 015:2018 section 7.1, delta-lambda = 1 nm).
    const double yIntegral = cieYIntegral();
    set.xyzWeights_.assign(m, {0, 0, 0});
    for (std::size_t k = 0; k < m; ++k) {
        const auto [first, last] = set.hatSupportNm(k);
        const int begin = std::max(kCieCmfFirstNm, int(std::ceil(first)));
        const int end = std::min(kCieCmfLastNm, int(std::floor(last)));
        for (int nm = begin; nm <= end; ++nm) {
            const double h = set.hat(k, nm);
            const auto& cmf = kCie1931Cmf[nm - kCieCmfFirstNm];
            for (int c = 0; c < 3; ++c)
                set.xyzWeights_[k][c] += h * cmf[c] / yIntegral;
        }
    }
    return set;
}

std::array<double, 2> WavelengthSet::hatSupportNm(std::size_t k) const {
    DAISY_CHECK_OP(k, <, size());
    const double first = k == 0 ? domainStartNm_ : wavelengthsNm_[k - 1];
    const double last = k + 1 == size() ? domainEndNm_ : wavelengthsNm_[k + 1];
    return {first, last};
}

double WavelengthSet::hat(std::size_t k, double nm) const {
    DAISY_CHECK_OP(k, <, size());
    if (nm < domainStartNm_ || nm > domainEndNm_) return 0;
    const double lk = wavelengthsNm_[k];
    if (nm <= lk) {
        if (k == 0) return 1;
        const double previous = wavelengthsNm_[k - 1];
        return nm <= previous ? 0 : (nm - previous) / (lk - previous);
    }
    if (k + 1 == size()) return 1;
    const double next = wavelengthsNm_[k + 1];
    return nm >= next ? 0 : (next - nm) / (next - lk);
}

Xyz WavelengthSet::toXyz(std::span<const double> values) const {
    DAISY_CHECK_OP(values.size(), ==, size());
    Xyz xyz{0, 0, 0};
    for (std::size_t k = 0; k < size(); ++k) {
        for (int c = 0; c < 3; ++c)
            xyz[c] += values[k] * xyzWeights_[k][c];
    }
    return xyz;
}

Xyz WavelengthSet::reflectanceToXyz(std::span<const double> reflectance,
                                    std::span<const double> illuminant) const {
    DAISY_CHECK_OP(reflectance.size(), ==, size());
    DAISY_CHECK_OP(illuminant.size(), ==, size());
    Xyz xyz{0, 0, 0};
    double whiteY = 0;
    for (std::size_t k = 0; k < size(); ++k) {
        for (int c = 0; c < 3; ++c)
            xyz[c] += reflectance[k] * illuminant[k] * xyzWeights_[k][c];
        whiteY += illuminant[k] * xyzWeights_[k][1];
    }
    if (whiteY <= 0) return {0, 0, 0};
    for (double& v : xyz)
        v /= whiteY;
    return xyz;
}

WavelengthSet daisyriotWavelengths() {
    return mustBuild(rangeNm(350, 650, 50), "daisyriot");
}

WavelengthSet meyer4Wavelengths() {
    return mustBuild({456.4, 490.9, 557.7, 631.4}, "meyer4");
}

WavelengthSet visibleWavelengths() {
    return mustBuild(rangeNm(400, 700, 20), "visible");
}

WavelengthSet autoWavelengths() {
    return mustBuild(rangeNm(400, 700, 10), "400:700:10");
}

WavelengthSet fineWavelengths() {
    return mustBuild(rangeNm(360, 830, 5), "fine");
}

WavelengthSet withUvExcitation(const WavelengthSet& base, bool sceneHasUvLights,
                               bool sceneHasFluorescence) {
    if (!sceneHasUvLights || !sceneHasFluorescence) return base;
    std::vector<double> nm;
    for (double uv : kUvExcitationNm) {
        if (uv < base.wavelengthNm(0) - kUvGapNm) nm.push_back(uv);
    }
    if (nm.empty()) return base;
    nm.insert(nm.end(), base.wavelengthsNm().begin(), base.wavelengthsNm().end());
    return mustBuild(std::move(nm), base.name() + "+uv");
}

Expected<WavelengthSet> makeWavelengthSet(const WavelengthSpec& spec, bool sceneHasUvLights,
                                          bool sceneHasFluorescence) {
    const auto withUv = [&](const WavelengthSet& base) {
        return withUvExcitation(base, sceneHasUvLights, sceneHasFluorescence);
    };
    switch (spec.kind) {
        case WavelengthSpec::Kind::Range: {
            auto set = WavelengthSet::fromWavelengths(
                rangeNm(spec.startNm, spec.endNm, spec.stepNm),
                concat(spec.startNm, ':', spec.endNm, ':', spec.stepNm));
            if (!set) return set.error();
            return withUv(*set);
        }
        case WavelengthSpec::Kind::List:
            return WavelengthSet::fromWavelengths(spec.listNm, "list");
        case WavelengthSpec::Kind::Preset:
            break;
    }
    if (spec.preset == "daisyriot") return withUv(daisyriotWavelengths());
    if (spec.preset == "meyer4") return withUv(meyer4Wavelengths());
    if (spec.preset == "visible") return withUv(visibleWavelengths());
    if (spec.preset == "auto") return withUv(autoWavelengths());
    if (spec.preset == "fine") return withUv(fineWavelengths());
    return Error{concat("unknown wavelength preset '", spec.preset,
                        "'; known: daisyriot, meyer4, visible, fine, auto")};
}

}  // namespace daisy
