#include "spectral/fluorescence.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/check.h"
#include "core/strings.h"
#include "spectral/presets.h"
#include "spectral/rgb_upsampling.h"
#include "spectral/spectrum.h"

namespace daisy {
namespace {

// Peaks, widths and yields: docs/materials.md has the sources. Absorption peaks (the fraction a
// coat absorbs at its peak) are our choice: a layer dense enough to look strongly coloured.
constexpr std::array<FluorophoreData, 4> kFluorophores = {{
    // Stilbene-type optical brightener: absorbs 340-370 nm, emits blue 420-470 nm.
    {"brightener", 350, 50, 0.9, 435, 60, 0.7},
    // Fluorescein dianion (basic solution): absorption 490 nm, emission 515 nm, yield 0.93.
    {"fluorescein", 490, 40, 0.8, 515, 35, 0.93},
    // Rhodamine 6G in ethanol: absorption 530 nm, emission 555 nm, yield 0.95.
    {"rhodamine6g", 530, 40, 0.8, 555, 40, 0.95},
    // Yellow highlighter ink (pyranine, basic form): absorption 454 nm, emission 511 nm.
    {"neon", 454, 50, 0.9, 511, 45, 0.8},
}};

constexpr double kFluorescentColorFirstNm = 300, kFluorescentColorPlateauEndNm = 400,
                 kFluorescentColorEndNm = 420;

std::string atNm(double nm) {
    return concat(nm, " nm");
}

ReradiationMatrix diagonal(std::span<const double> values) {
    ReradiationMatrix m;
    m.size = values.size();
    m.values.assign(m.size * m.size, 0.0);
    for (std::size_t i = 0; i < m.size; ++i)
        m(i, i) = values[i];
    return m;
}

Expected<std::vector<double>> sampleReflectance(const WavelengthSet& set,
                                                const std::optional<SpectrumSpec>& reflectance,
                                                const Rgb& baseColor, std::string_view where) {
    if (reflectance) {
        auto samples = sampleSpectrum(set, *reflectance, SpectrumRole::Reflectance);
        if (!samples) return withContext(samples.error(), concat(where, ": reflectance"));
        return samples;
    }
    return sampleSpectrum(set, Spectrum::reflectance(rgbToReflectance(baseColor)),
                          SpectrumRole::Reflectance);
}

Expected<void> checkFraction(std::span<const double> values, const WavelengthSet& set,
                             std::string_view where, std::string_view what) {
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (!std::isfinite(values[i]) || values[i] < -kEnergyTolerance ||
            values[i] > 1 + kEnergyTolerance) {
            return Error{concat(where, ": ", what, ' ', values[i], " at ",
                                atNm(set.wavelengthNm(i)), " is outside [0, 1]")};
        }
    }
    return {};
}

}  // namespace

bool ReradiationMatrix::isDiagonal() const {
    for (std::size_t o = 0; o < size; ++o) {
        for (std::size_t i = 0; i < size; ++i) {
            if (o != i && (*this)(o, i) != 0) return false;
        }
    }
    return true;
}

double ReradiationMatrix::powerColumnSum(const WavelengthSet& set, std::size_t i) const {
    double sum = 0;
    for (std::size_t o = 0; o < size; ++o)
        sum += (*this)(o, i) * set.binWidthNm(o) / set.binWidthNm(i);
    return sum;
}

Expected<void> validateReradiationMatrix(const WavelengthSet& set, const ReradiationMatrix& m,
                                         std::string_view where) {
    if (m.size != set.size() || m.values.size() != m.size * m.size) {
        return Error{concat(where, ": re-radiation matrix is ", m.size, " x ", m.size, " (",
                            m.values.size(), " values) but the wavelength set '", set.name(),
                            "' has ", set.size(), " samples")};
    }
    for (std::size_t o = 0; o < m.size; ++o) {
        for (std::size_t i = 0; i < m.size; ++i) {
            const double v = m(o, i);
            if (!std::isfinite(v) || v < 0) {
                return Error{concat(where, ": re-radiation from ", atNm(set.wavelengthNm(i)),
                                    " to ", atNm(set.wavelengthNm(o)), " is ", v,
                                    "; entries must be finite and >= 0")};
            }
            if (o < i && v != 0) {
                return Error{concat(where, ": re-radiation ", v, " from ",
                                    atNm(set.wavelengthNm(i)), " to the shorter ",
                                    atNm(set.wavelengthNm(o)),
                                    "; light may only move to longer wavelengths (the matrix "
                                    "must be lower triangular)")};
            }
        }
    }
    for (std::size_t i = 0; i < m.size; ++i) {
        const double sum = m.powerColumnSum(set, i);
        if (sum > 1 + kEnergyTolerance) {
            return Error{concat(where, ": light at ", atNm(set.wavelengthNm(i)), " leaves with ",
                                sum,
                                " times its power (column sum over 1): it would create energy")};
        }
    }
    return {};
}

Expected<void> validateFluorescenceMatrix(const FluorescenceMatrix& matrix,
                                          std::string_view where) {
    const std::vector<double>& nm = matrix.wavelengthsNm;
    const std::size_t n = nm.size();
    if (n == 0) return Error{concat(where, ": fluorescence matrix has no wavelengths")};
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(nm[i]) || (i > 0 && nm[i] <= nm[i - 1])) {
            return Error{concat(where, ": fluorescence matrix wavelength ", nm[i],
                                " nm is not finite and strictly ascending")};
        }
    }
    if (matrix.values.size() != n) {
        return Error{concat(where, ": fluorescence matrix has ", matrix.values.size(), " rows for ",
                            n, " wavelengths")};
    }
    for (std::size_t o = 0; o < n; ++o) {
        if (matrix.values[o].size() != n) {
            return Error{concat(where, ": fluorescence matrix row ", o, " (", atNm(nm[o]), ") has ",
                                matrix.values[o].size(), " values for ", n, " wavelengths")};
        }
        for (std::size_t i = 0; i < n; ++i) {
            const double v = matrix.values[o][i];
            if (!std::isfinite(v) || v < 0) {
                return Error{concat(where, ": fluorescence matrix entry from ", atNm(nm[i]), " to ",
                                    atNm(nm[o]), " is ", v, "; must be finite and >= 0")};
            }
            if (o < i && v != 0) {
                return Error{concat(where, ": fluorescence matrix entry ", v, " from ", atNm(nm[i]),
                                    " to the shorter ", atNm(nm[o]),
                                    "; entries above the diagonal must be 0")};
            }
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        double sum = 0;
        for (std::size_t o = 0; o < n; ++o)
            sum += matrix.values[o][i];
        if (sum > 1 + kEnergyTolerance) {
            return Error{concat(where, ": fluorescence matrix column at ", atNm(nm[i]), " sums to ",
                                sum, ", over 1: it would create energy")};
        }
    }
    return {};
}

Expected<ReradiationMatrix> reradiationMatrix(const WavelengthSet& set,
                                              std::span<const double> reflectance,
                                              std::span<const double> absorption,
                                              std::span<const double> emission, double quantumYield,
                                              std::string_view where) {
    const std::size_t m = set.size();
    DAISY_CHECK(reflectance.size() == m && absorption.size() == m && emission.size() == m);
    if (!std::isfinite(quantumYield) || quantumYield < 0 || quantumYield > 1) {
        return Error{concat(where, ": quantum yield ", quantumYield, " is outside [0, 1]")};
    }
    if (auto ok = checkFraction(reflectance, set, where, "reflectance"); !ok) return ok.error();
    if (auto ok = checkFraction(absorption, set, where, "fluorophore absorption"); !ok) {
        return ok.error();
    }
    for (std::size_t i = 0; i < m; ++i) {
        if (reflectance[i] + absorption[i] > 1 + kEnergyTolerance) {
            return Error{concat(where, ": reflectance ", formatNumber(reflectance[i], 4),
                                " + fluorophore absorption ", formatNumber(absorption[i], 4), " = ",
                                formatNumber(reflectance[i] + absorption[i], 4), " at ",
                                atNm(set.wavelengthNm(i)),
                                " exceeds 1 (rho + a <= 1, DESIGN.md section 5)")};
        }
        if (!std::isfinite(emission[i]) || emission[i] < 0) {
            return Error{concat(where, ": fluorescence emission ", emission[i], " at ",
                                atNm(set.wavelengthNm(i)), " is not a finite number >= 0")};
        }
    }

    ReradiationMatrix matrix = diagonal(reflectance);
    // Emitted power above sample i, sum_{o > i} e_o w_o, accumulated from the long end.
    std::vector<double> emittedAbove(m, 0.0);
    for (std::size_t i = m; i-- > 1;)
        emittedAbove[i - 1] = emittedAbove[i] + emission[i] * set.binWidthNm(i);
    for (std::size_t i = 0; i < m; ++i) {
        const double absorbed = quantumYield * absorption[i];
        if (absorbed == 0 || emittedAbove[i] <= 0) continue;
        const double li = set.wavelengthNm(i), wi = set.binWidthNm(i);
        for (std::size_t o = i + 1; o < m; ++o) {
            // Q a_i (l_i / l_o) p_i(o) (w_i / w_o), p_i(o) = e_o w_o / emittedAbove[i].
            matrix(o, i) =
                absorbed * (li / set.wavelengthNm(o)) * emission[o] * wi / emittedAbove[i];
        }
    }
    if (auto ok = validateReradiationMatrix(set, matrix, where); !ok) return ok.error();
    return matrix;
}

Expected<ReradiationMatrix> resampleFluorescenceMatrix(const WavelengthSet& set,
                                                       const FluorescenceMatrix& matrix,
                                                       std::string_view where) {
    if (auto ok = validateFluorescenceMatrix(matrix, where); !ok) return ok.error();
    const std::vector<double>& g = matrix.wavelengthsNm;
    const auto& v = matrix.values;
    const std::size_t n = g.size(), m = set.size();
    ReradiationMatrix result;
    result.size = m;
    result.values.assign(m * m, 0.0);
    // Power fractions F[p][j] first; densities at the end.
    for (std::size_t j = 0; j < m; ++j) {
        const double l = set.wavelengthNm(j);
        // Interpolation between matrix columns a and b with weight t on b.
        std::size_t a = 0, b = 0;
        double t = 0;
        // Outside the matrix's wavelengths only its end reflectance is known: no fluorescence.
        const bool inside = l >= g.front() && l <= g.back();
        if (l <= g.front()) {
            a = b = 0;
        } else if (l >= g.back()) {
            a = b = n - 1;
        } else {
            b = std::size_t(std::upper_bound(g.begin(), g.end(), l) - g.begin());
            a = b - 1;
            t = (l - g[a]) / (g[b] - g[a]);
        }
        result(j, j) += (1 - t) * v[a][a] + t * v[b][b];
        if (!inside) continue;
        for (std::size_t o = 0; o < n; ++o) {
            const double fraction = (1 - t) * (o > a ? v[o][a] : 0.0) + t * (o > b ? v[o][b] : 0.0);
            if (fraction == 0) continue;
            // Split between the set samples around g[o] (> l) by their hats; the share that
            // lands on sample j itself is re-emission within j's bin: it joins the diagonal.
            for (std::size_t p = j; p < m; ++p) {
                const double share = set.hat(p, std::min(g[o], set.domainEndNm()));
                if (share > 0) result(p, j) += fraction * share;
            }
        }
    }
    for (std::size_t p = 0; p < m; ++p) {
        for (std::size_t j = 0; j < p; ++j)
            result(p, j) *= set.binWidthNm(j) / set.binWidthNm(p);
    }
    if (auto ok = validateReradiationMatrix(set, result, where); !ok) return ok.error();
    return result;
}

std::span<const FluorophoreData> fluorophoreData() {
    return kFluorophores;
}

Expected<FluorescenceParams> fluorophorePresetParams(std::string_view name) {
    const auto canonical = canonicalFluorophorePreset(name);
    if (canonical) {
        for (const FluorophoreData& f : kFluorophores) {
            if (f.name != *canonical) continue;
            FluorescenceParams params;
            params.absorption = SpectrumSpec{
                GaussianSpectrum{f.absorptionPeakNm, f.absorptionFwhmNm}, f.peakAbsorption};
            params.emission = SpectrumSpec{GaussianSpectrum{f.emissionPeakNm, f.emissionFwhmNm}};
            params.quantumYield = f.quantumYield;
            return params;
        }
    }
    return Error{concat("unknown fluorophore preset '", name,
                        "'; known: ", joinNames(fluorophorePresetNames()))};
}

Expected<Fluorophore> makeFluorophore(const FluorescenceParams& params) {
    auto absorption = makeSpectrum(params.absorption, SpectrumRole::Reflectance);
    if (!absorption) return withContext(absorption.error(), "fluorescence absorption");
    auto emission = makeSpectrum(params.emission, SpectrumRole::Emission);
    if (!emission) return withContext(emission.error(), "fluorescence emission");
    return Fluorophore{std::move(*absorption), std::move(*emission), params.quantumYield};
}

Fluorophore fluorescentColorFluorophore(const FluorescentColor& color) {
    double peak = 0;
    for (double c : color.rgb)
        peak = std::max(peak, std::isfinite(c) ? std::clamp(c, 0.0, 1.0) : 0.0);
    Fluorophore fluorophore;
    fluorophore.absorption = Spectrum::tabulated(
        {kFluorescentColorFirstNm, kFluorescentColorPlateauEndNm, kFluorescentColorEndNm},
        {kFluorescentColorAbsorption, kFluorescentColorAbsorption, 0.0}, true);
    if (peak > 0) {
        Rgb shape;
        for (int c = 0; c < 3; ++c)
            shape[c] = std::isfinite(color.rgb[c]) ? std::clamp(color.rgb[c], 0.0, 1.0) / peak : 0;
        fluorophore.emission = Spectrum::emission(rgbToEmission(shape)).timesWavelength();
    }
    fluorophore.quantumYield = peak;
    return fluorophore;
}

Expected<ReradiationMatrix> materialReradiationMatrix(
    const WavelengthSet& set, const std::optional<SpectrumSpec>& reflectance, const Rgb& baseColor,
    const std::optional<FluorescenceSpec>& fluorescence, std::string_view where) {
    if (fluorescence && std::holds_alternative<FluorescenceMatrix>(*fluorescence)) {
        return resampleFluorescenceMatrix(set, std::get<FluorescenceMatrix>(*fluorescence),
                                          concat(where, ": fluorescence matrix"));
    }
    auto rho = sampleReflectance(set, reflectance, baseColor, where);
    if (!rho) return rho.error();
    if (!fluorescence) {
        if (auto ok = checkFraction(*rho, set, where, "reflectance"); !ok) return ok.error();
        return diagonal(*rho);
    }

    Fluorophore fluorophore;
    bool layered = true;
    if (const auto* preset = std::get_if<FluorophorePreset>(&*fluorescence)) {
        auto params = fluorophorePresetParams(preset->name);
        if (!params) return withContext(params.error(), std::string(where));
        auto made = makeFluorophore(*params);
        DAISY_CHECK(made.ok());
        fluorophore = std::move(*made);
    } else if (const auto* color = std::get_if<FluorescentColor>(&*fluorescence)) {
        fluorophore = fluorescentColorFluorophore(*color);
    } else {
        auto made = makeFluorophore(std::get<FluorescenceParams>(*fluorescence));
        if (!made) return withContext(made.error(), std::string(where));
        fluorophore = std::move(*made);
        layered = false;
    }
    const std::vector<double> absorption =
        sampleSpectrum(set, fluorophore.absorption, SpectrumRole::Reflectance);
    const std::vector<double> emission =
        sampleSpectrum(set, fluorophore.emission, SpectrumRole::Emission);
    if (layered) {
        for (std::size_t i = 0; i < set.size(); ++i)
            (*rho)[i] *= 1 - std::clamp(absorption[i], 0.0, 1.0);
    }
    return reradiationMatrix(set, *rho, absorption, emission, fluorophore.quantumYield, where);
}

Expected<std::vector<double>> materialEmission(const WavelengthSet& set,
                                               const std::optional<SpectrumSpec>& emission,
                                               const Rgb& emissiveRgb, std::string_view where) {
    if (emission) {
        auto samples = sampleSpectrum(set, *emission, SpectrumRole::Emission);
        if (!samples) return withContext(samples.error(), concat(where, ": emission"));
        return samples;
    }
    if (emissiveRgb[0] <= 0 && emissiveRgb[1] <= 0 && emissiveRgb[2] <= 0) {
        return std::vector<double>(set.size(), 0.0);
    }
    return sampleSpectrum(set, Spectrum::emission(rgbToEmission(emissiveRgb)),
                          SpectrumRole::Emission);
}

}  // namespace daisy
