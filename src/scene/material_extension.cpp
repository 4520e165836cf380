#include "scene/material_extension.h"

#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <span>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/strings.h"
#include "spectral/presets.h"
#include "spectral/wavelength_spec.h"

namespace daisy {
namespace {

using nlohmann::json;

// What a spectrum describes; decides the allowed shapes and the range of its values.
enum class SpectrumRole { Reflectance, Absorption, Emission, FluorophoreEmission };

constexpr double kMinBlackbodyK = 100.0;
constexpr double kMaxBlackbodyK = 100000.0;
constexpr double kColumnSumTolerance = 1e-9;  // slack on "every column of M sums to <= 1"
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Emission values and scales above this would overflow the solve (B sums E over bounces and the
// D65 and blackbody shapes multiply it); no physical source comes near (the Sun's surface emits
// about 1e5 W m^-2 nm^-1).
constexpr double kMaxEmission = 1e30;

constexpr std::array<std::string_view, 3> kExtensionMembers = {"reflectance", "emission",
                                                               "fluorescence"};
constexpr std::array<std::string_view, 7> kSpectrumMembers = {
    "wavelengths", "values", "rgb", "preset", "blackbody", "gaussian", "scale"};
constexpr std::array<std::string_view, 2> kGaussianMembers = {"peak", "fwhm"};
constexpr std::array<std::string_view, 5> kFluorescenceMembers = {
    "preset", "absorption", "emission", "quantumYield", "matrix"};
constexpr std::array<std::string_view, 2> kMatrixMembers = {"wavelengths", "values"};

std::string member(const std::string& path, std::string_view key) {
    return path.empty() ? std::string(key) : concat(path, '.', key);
}

std::string element(const std::string& path, std::size_t index) {
    return concat(path, '[', index, ']');
}

Error fail(const std::string& path, const std::string& problem) {
    return Error{path + ": " + problem};
}

// "string \"abc\"" for type errors, shortened for long values.
std::string describe(const json& value) {
    if (value.is_null()) return "null";
    std::string text = value.dump();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return concat(value.type_name(), ' ', text);
}

bool isReflectanceLike(SpectrumRole role) {
    return role == SpectrumRole::Reflectance || role == SpectrumRole::Absorption;
}

const char* roleName(SpectrumRole role) {
    constexpr const char* kNames[] = {"reflectance", "absorption", "emission",
                                      "fluorescence emission"};
    return kNames[static_cast<int>(role)];
}

Expected<void> requireObject(const json& value, const std::string& path,
                             std::span<const std::string_view> allowed) {
    if (!value.is_object()) return fail(path, "expected an object, got " + describe(value));
    for (const auto& item : value.items()) {
        bool known = false;
        for (std::string_view name : allowed)
            known = known || item.key() == name;
        if (!known) {
            return fail(member(path, item.key()), "unknown member; allowed: " + joinNames(allowed));
        }
    }
    return {};
}

// A finite number in [low, high]; `unit` (" nm", " K" or "") follows numbers in messages.
Expected<double> readNumber(const json& value, const std::string& path, double low = -kInfinity,
                            double high = kInfinity, const char* unit = "") {
    if (!value.is_number()) return fail(path, "expected a number, got " + describe(value));
    const double result = value.get<double>();
    if (!std::isfinite(result)) return fail(path, formatNumber(result) + " is not finite");
    if (result < low && low == 0 && high > 1) {
        return fail(path, formatNumber(result) + unit + " is negative");
    }
    if (result < low || result > high) {
        return fail(path,
                    concat(formatNumber(result), unit, " is outside [", formatNumber(low), ", ",
                           formatNumber(high), "]", unit));
    }
    return result;
}

Expected<std::vector<double>> readNumbers(const json& value, const std::string& path,
                                          double low = -kInfinity, double high = kInfinity,
                                          const char* unit = "") {
    if (!value.is_array())
        return fail(path, "expected an array of numbers, got " + describe(value));
    std::vector<double> result;
    for (std::size_t i = 0; i < value.size(); ++i) {
        auto item = readNumber(value[i], element(path, i), low, high, unit);
        if (!item) return item.error();
        result.push_back(*item);
    }
    return result;
}

// At least two, strictly ascending, within [kMinWavelengthNm, kMaxWavelengthNm].
Expected<std::vector<double>> readWavelengths(const json& value, const std::string& path) {
    auto wavelengths = readNumbers(value, path, kMinWavelengthNm, kMaxWavelengthNm, " nm");
    if (!wavelengths) return wavelengths.error();
    const std::vector<double>& nm = *wavelengths;
    if (nm.size() < 2) return fail(path, concat("needs at least 2 wavelengths, got ", nm.size()));
    for (std::size_t i = 1; i < nm.size(); ++i) {
        if (nm[i] <= nm[i - 1]) {
            return fail(element(path, i),
                        concat(formatNumber(nm[i]), " nm does not follow ", formatNumber(nm[i - 1]),
                               " nm; wavelengths must be strictly ascending"));
        }
    }
    return wavelengths;
}

// Spectrum values (tabulated or RGB) in the role's range: [0, 1] for reflectance and
// absorption, >= 0 otherwise, and not all zero for a fluorescence emission shape.
Expected<std::vector<double>> readValues(const json& value, const std::string& path,
                                         SpectrumRole role) {
    auto values = readNumbers(value, path, 0,
                              isReflectanceLike(role)              ? 1
                                  : role == SpectrumRole::Emission ? kMaxEmission
                                                                   : kInfinity);
    if (!values) return values.error();
    bool allZero = true;
    for (double v : *values)
        allZero = allZero && v == 0;
    if (role == SpectrumRole::FluorophoreEmission && allZero) {
        return fail(path, "all values are 0; a fluorescence emission shape needs a non-zero value");
    }
    return values;
}

Expected<SpectrumShape> parseTabulated(const json& object, const std::string& path,
                                       SpectrumRole role) {
    if (!object.contains("wavelengths")) return fail(path, "'values' given without 'wavelengths'");
    if (!object.contains("values")) return fail(path, "'wavelengths' given without 'values'");
    auto wavelengths = readWavelengths(object["wavelengths"], member(path, "wavelengths"));
    if (!wavelengths) return wavelengths.error();
    const std::string valuesPath = member(path, "values");
    auto values = readValues(object["values"], valuesPath, role);
    if (!values) return values.error();
    if (values->size() != wavelengths->size()) {
        return fail(valuesPath,
                    concat(values->size(), " values for ", wavelengths->size(),
                           " wavelengths; give one value per wavelength"));
    }
    return SpectrumShape{TabulatedSpectrum{std::move(*wavelengths), std::move(*values)}};
}

Expected<SpectrumShape> parseRgb(const json& value, const std::string& path, SpectrumRole role) {
    if (!value.is_array() || value.size() != 3) {
        return fail(path, "expected an array of 3 numbers [r, g, b], got " + describe(value));
    }
    auto values = readValues(value, path, role);
    if (!values) return values.error();
    return SpectrumShape{RgbSpectrum{{(*values)[0], (*values)[1], (*values)[2]}}};
}

Expected<SpectrumShape> parsePreset(const json& value, const std::string& path) {
    if (!value.is_string()) return fail(path, "expected a preset name, got " + describe(value));
    const std::string name = value.get<std::string>();
    auto canonical = canonicalIlluminantPreset(name);
    if (!canonical) {
        return fail(path,
                    concat("unknown illuminant preset '", name,
                           "'; known: ", joinNames(illuminantPresetNames())));
    }
    return SpectrumShape{PresetSpectrum{*canonical}};
}

Expected<SpectrumShape> parseGaussian(const json& value, const std::string& path) {
    if (auto checked = requireObject(value, path, kGaussianMembers); !checked) {
        return checked.error();
    }
    for (const char* key : {"peak", "fwhm"}) {
        if (!value.contains(key)) return fail(path, concat("'", key, "' is missing"));
    }
    auto peak =
        readNumber(value["peak"], member(path, "peak"), kMinWavelengthNm, kMaxWavelengthNm, " nm");
    if (!peak) return peak.error();
    auto fwhm = readNumber(value["fwhm"], member(path, "fwhm"));
    if (!fwhm) return fwhm.error();
    if (*fwhm <= 0) return fail(member(path, "fwhm"), formatNumber(*fwhm) + " nm is not positive");
    return SpectrumShape{GaussianSpectrum{*peak, *fwhm}};
}

// One spectrum object: exactly one shape key plus an optional "scale".
Expected<SpectrumSpec> parseSpectrum(const json& object, const std::string& path,
                                     SpectrumRole role) {
    if (auto checked = requireObject(object, path, kSpectrumMembers); !checked) {
        return checked.error();
    }
    std::vector<std::string_view> shapes;
    if (object.contains("wavelengths") || object.contains("values")) {
        shapes.push_back("wavelengths+values");
    }
    for (std::string_view key : {"rgb", "preset", "blackbody", "gaussian"}) {
        if (object.contains(key)) shapes.push_back(key);
    }
    if (shapes.size() != 1) {
        return fail(path,
                    shapes.empty() ? concat("no ", roleName(role), " spectrum given; give one of ",
                                            "wavelengths+values, rgb, preset, blackbody, gaussian")
                                   : concat("gives both ", shapes[0], " and ", shapes[1],
                                            "; a spectrum has exactly one shape"));
    }
    const std::string_view kind = shapes[0];
    if (isReflectanceLike(role) && (kind == "preset" || kind == "blackbody")) {
        return fail(member(path, kind),
                    concat(roleName(role), " cannot be ",
                           kind == "preset" ? "an illuminant preset" : "a blackbody",
                           "; use wavelengths+values, rgb or gaussian"));
    }

    SpectrumSpec spec;
    if (object.contains("scale")) {
        // Shapes peak at 1 (or stay within [0, 1]), so a scale <= 1 keeps a reflectance valid.
        const std::string scalePath = member(path, "scale");
        auto scale =
            readNumber(object["scale"], scalePath, 0, isReflectanceLike(role) ? 1.0 : kMaxEmission);
        if (!scale) return scale.error();
        if (role == SpectrumRole::FluorophoreEmission && *scale == 0) {
            return fail(scalePath, "0 makes the fluorescence emission shape zero");
        }
        spec.scale = *scale;
    }
    Expected<SpectrumShape> shape = Error{};
    if (kind == "wavelengths+values") {
        shape = parseTabulated(object, path, role);
    } else if (kind == "rgb") {
        shape = parseRgb(object["rgb"], member(path, "rgb"), role);
    } else if (kind == "preset") {
        shape = parsePreset(object["preset"], member(path, "preset"));
    } else if (kind == "gaussian") {
        shape = parseGaussian(object["gaussian"], member(path, "gaussian"));
    } else {
        auto kelvin = readNumber(object["blackbody"], member(path, "blackbody"), kMinBlackbodyK,
                                 kMaxBlackbodyK, " K");
        if (!kelvin) return kelvin.error();
        shape = SpectrumShape{BlackbodySpectrum{*kelvin}};
    }
    if (!shape) return shape.error();
    spec.shape = std::move(*shape);
    return spec;
}

// A measured re-radiation matrix M[o][i] (DESIGN.md section 5): square, finite, >= 0, lower
// triangular in wavelength order, every column sum <= 1.
Expected<FluorescenceMatrix> parseMatrix(const json& object, const std::string& path) {
    if (auto checked = requireObject(object, path, kMatrixMembers); !checked) {
        return checked.error();
    }
    for (const char* key : {"wavelengths", "values"}) {
        if (!object.contains(key)) return fail(path, concat("'", key, "' is missing"));
    }
    FluorescenceMatrix matrix;
    auto wavelengths = readWavelengths(object["wavelengths"], member(path, "wavelengths"));
    if (!wavelengths) return wavelengths.error();
    matrix.wavelengthsNm = std::move(*wavelengths);
    const std::vector<double>& nm = matrix.wavelengthsNm;
    const std::size_t n = nm.size();

    const std::string valuesPath = member(path, "values");
    const json& rows = object["values"];
    if (!rows.is_array() || rows.size() != n) {
        return fail(valuesPath,
                    concat("expected ", n, " rows of ", n, " numbers (one per wavelength), got ",
                           describe(rows)));
    }
    for (std::size_t o = 0; o < n; ++o) {
        const std::string rowPath = element(valuesPath, o);
        if (!rows[o].is_array() || rows[o].size() != n) {
            return fail(rowPath, concat("expected ", n, " numbers, got ", describe(rows[o])));
        }
        auto row = readNumbers(rows[o], rowPath, 0, kInfinity);
        if (!row) return row.error();
        for (std::size_t i = o + 1; i < n; ++i) {
            if ((*row)[i] != 0) {
                return fail(element(rowPath, i),
                            concat(formatNumber((*row)[i]), " would re-emit light from ",
                                   formatNumber(nm[i]), " nm at the shorter ", formatNumber(nm[o]),
                                   " nm; entries above the diagonal must be 0"));
            }
        }
        matrix.values.push_back(std::move(*row));
    }
    for (std::size_t i = 0; i < n; ++i) {
        double sum = 0;
        for (std::size_t o = 0; o < n; ++o)
            sum += matrix.values[o][i];
        if (sum > 1 + kColumnSumTolerance) {
            return fail(valuesPath,
                        concat("column ", i, " (", formatNumber(nm[i]), " nm) sums to ",
                               formatNumber(sum), ", over 1: it would create energy"));
        }
    }
    return matrix;
}

Expected<FluorescenceSpec> parseFluorescence(const json& object, const std::string& path) {
    if (auto checked = requireObject(object, path, kFluorescenceMembers); !checked) {
        return checked.error();
    }
    const bool hasPreset = object.contains("preset");
    const bool hasMatrix = object.contains("matrix");
    const bool hasParams = object.contains("absorption") || object.contains("emission") ||
        object.contains("quantumYield");
    const int forms = int(hasPreset) + int(hasMatrix) + int(hasParams);
    if (forms != 1) {
        return fail(path,
                    concat(forms == 0 ? "give" : "give only",
                           " one of: preset; absorption + emission + quantumYield; matrix"));
    }
    if (hasPreset) {
        const json& value = object["preset"];
        const std::string name = value.is_string() ? value.get<std::string>() : std::string();
        auto canonical = canonicalFluorophorePreset(name);
        if (!canonical) {
            return fail(
                member(path, "preset"),
                concat(value.is_string() ? "unknown fluorophore preset '" + name + "'"
                                         : "expected a fluorophore name, got " + describe(value),
                       "; known: ", joinNames(fluorophorePresetNames())));
        }
        return FluorescenceSpec{FluorophorePreset{*canonical}};
    }
    if (hasMatrix) {
        auto matrix = parseMatrix(object["matrix"], member(path, "matrix"));
        if (!matrix) return matrix.error();
        return FluorescenceSpec{std::move(*matrix)};
    }
    for (const char* key : {"absorption", "emission", "quantumYield"}) {
        if (!object.contains(key)) {
            return fail(path,
                        concat("'", key, "' is missing; absorption, emission and quantumYield are ",
                               "all required"));
        }
    }
    FluorescenceParams params;
    auto absorption =
        parseSpectrum(object["absorption"], member(path, "absorption"), SpectrumRole::Absorption);
    if (!absorption) return absorption.error();
    params.absorption = std::move(*absorption);
    auto emission = parseSpectrum(object["emission"], member(path, "emission"),
                                  SpectrumRole::FluorophoreEmission);
    if (!emission) return emission.error();
    params.emission = std::move(*emission);
    auto yield = readNumber(object["quantumYield"], member(path, "quantumYield"), 0, 1);
    if (!yield) return yield.error();
    params.quantumYield = *yield;
    return FluorescenceSpec{std::move(params)};
}

Expected<MaterialExtension> parseExtension(const json& object, const std::string& where) {
    if (auto checked = requireObject(object, where, kExtensionMembers); !checked) {
        return checked.error();
    }
    MaterialExtension extension;
    if (object.contains("reflectance")) {
        auto reflectance = parseSpectrum(object["reflectance"], member(where, "reflectance"),
                                         SpectrumRole::Reflectance);
        if (!reflectance) return reflectance.error();
        extension.reflectance = std::move(*reflectance);
    }
    if (object.contains("emission")) {
        auto emission =
            parseSpectrum(object["emission"], member(where, "emission"), SpectrumRole::Emission);
        if (!emission) return emission.error();
        extension.emission = std::move(*emission);
    }
    if (object.contains("fluorescence") && object["fluorescence"].is_null()) {
        extension.removesFluorescence = true;
    } else if (object.contains("fluorescence")) {
        auto fluorescence =
            parseFluorescence(object["fluorescence"], member(where, "fluorescence"));
        if (!fluorescence) return fluorescence.error();
        extension.fluorescence = std::move(*fluorescence);
    }
    return extension;
}

json spectrumToJson(const SpectrumSpec& spec) {
    json out = json::object();
    std::visit(
        [&](const auto& shape) {
            using Shape = std::decay_t<decltype(shape)>;
            if constexpr (std::is_same_v<Shape, RgbSpectrum>) {
                out["rgb"] = shape.rgb;
            } else if constexpr (std::is_same_v<Shape, TabulatedSpectrum>) {
                out["wavelengths"] = shape.wavelengthsNm;
                out["values"] = shape.values;
            } else if constexpr (std::is_same_v<Shape, PresetSpectrum>) {
                out["preset"] = shape.name;
            } else if constexpr (std::is_same_v<Shape, BlackbodySpectrum>) {
                out["blackbody"] = shape.temperatureK;
            } else {
                out["gaussian"] = {{"peak", shape.peakNm}, {"fwhm", shape.fwhmNm}};
            }
        },
        spec.shape);
    if (spec.scale != 1.0) out["scale"] = spec.scale;
    return out;
}

}  // namespace

json materialExtensionToJson(const MaterialExtension& extension, bool* representable) {
    if (representable != nullptr) *representable = true;
    json out = json::object();
    if (extension.reflectance) out["reflectance"] = spectrumToJson(*extension.reflectance);
    if (extension.emission) out["emission"] = spectrumToJson(*extension.emission);
    if (extension.removesFluorescence) out["fluorescence"] = nullptr;
    if (!extension.fluorescence) return out;
    std::visit(
        [&](const auto& spec) {
            using Spec = std::decay_t<decltype(spec)>;
            if constexpr (std::is_same_v<Spec, FluorophorePreset>) {
                out["fluorescence"] = {{"preset", spec.name}};
            } else if constexpr (std::is_same_v<Spec, FluorescenceParams>) {
                out["fluorescence"] = {{"absorption", spectrumToJson(spec.absorption)},
                                       {"emission", spectrumToJson(spec.emission)},
                                       {"quantumYield", spec.quantumYield}};
            } else if constexpr (std::is_same_v<Spec, FluorescenceMatrix>) {
                out["fluorescence"] = {
                    {"matrix", {{"wavelengths", spec.wavelengthsNm}, {"values", spec.values}}}};
            } else if (representable != nullptr) {
                *representable = false;  // FluorescentColor: MTL only
            }
        },
        *extension.fluorescence);
    return out;
}

Expected<MaterialExtension> parseMaterialExtension(const nlohmann::json& object,
                                                   const std::string& where) {
    try {
        return parseExtension(object, where);
    } catch (const std::exception& e) {
        // Every access is type-checked first; this only keeps a library surprise in-module.
        return fail(where, concat("unexpected JSON error: ", e.what()));
    }
}

}  // namespace daisy
