#include "scene/material_extension.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "spectral/presets.h"

namespace daisy {
namespace {

using nlohmann::json;

const std::string kWhere = "materials[2].extensions.DAISY_materials_spectral";

Expected<MaterialExtension> parse(const std::string& text) {
    return parseMaterialExtension(json::parse(text), kWhere);
}

// The error message for `object`, which must fail to parse.
std::string errorOfJson(const json& object) {
    auto result = parseMaterialExtension(object, kWhere);
    EXPECT_FALSE(result.ok()) << "accepted: " << object.dump();
    return result.ok() ? std::string() : result.error().message;
}

std::string errorOf(const std::string& text) {
    return errorOfJson(json::parse(text));
}

// Expects `message` == kWhere + "." + suffix, i.e. the exact path and problem.
void expectError(const std::string& text, const std::string& suffix) {
    EXPECT_EQ(errorOf(text), kWhere + "." + suffix) << text;
}

TEST(MaterialExtension, EmptyObjectSetsNothing) {
    auto extension = parse("{}");
    ASSERT_TRUE(extension.ok()) << extension.error().message;
    EXPECT_FALSE(extension->reflectance);
    EXPECT_FALSE(extension->emission);
    EXPECT_FALSE(extension->fluorescence);
}

TEST(MaterialExtension, TabulatedReflectance) {
    auto extension =
        parse(R"({"reflectance": {"wavelengths": [400, 550, 700], "values": [0.1, 0.5, 0.9]}})");
    ASSERT_TRUE(extension.ok()) << extension.error().message;
    ASSERT_TRUE(extension->reflectance);
    EXPECT_EQ(extension->reflectance->scale, 1.0);  // the documented default
    const auto& table = std::get<TabulatedSpectrum>(extension->reflectance->shape);
    EXPECT_EQ(table.wavelengthsNm, (std::vector<double>{400, 550, 700}));
    EXPECT_EQ(table.values, (std::vector<double>{0.1, 0.5, 0.9}));
}

TEST(MaterialExtension, RgbAndGaussianReflectance) {
    auto rgb = parse(R"({"reflectance": {"rgb": [0.25, 0.5, 1]}})");
    ASSERT_TRUE(rgb.ok()) << rgb.error().message;
    EXPECT_EQ(std::get<RgbSpectrum>(rgb->reflectance->shape).rgb,
              (std::array<double, 3>{0.25, 0.5, 1}));

    auto gaussian =
        parse(R"({"reflectance": {"gaussian": {"peak": 520, "fwhm": 40}, "scale": 0.5}})");
    ASSERT_TRUE(gaussian.ok()) << gaussian.error().message;
    const auto& shape = std::get<GaussianSpectrum>(gaussian->reflectance->shape);
    EXPECT_EQ(shape.peakNm, 520);
    EXPECT_EQ(shape.fwhmNm, 40);
    EXPECT_EQ(gaussian->reflectance->scale, 0.5);
}

TEST(MaterialExtension, EmissionForms) {
    // Preset matching is case-insensitive and stores the canonical spelling (presets.h).
    auto preset = parse(R"({"emission": {"preset": "BlackLight", "scale": 20}})");
    ASSERT_TRUE(preset.ok()) << preset.error().message;
    EXPECT_EQ(std::get<PresetSpectrum>(preset->emission->shape).name, "blacklight");
    EXPECT_EQ(preset->emission->scale, 20);
    auto d65 = parse(R"({"emission": {"preset": "d65"}})");
    ASSERT_TRUE(d65.ok()) << d65.error().message;
    EXPECT_EQ(std::get<PresetSpectrum>(d65->emission->shape).name, "D65");

    auto blackbody = parse(R"({"emission": {"blackbody": 2700, "scale": 5}})");
    ASSERT_TRUE(blackbody.ok()) << blackbody.error().message;
    EXPECT_EQ(std::get<BlackbodySpectrum>(blackbody->emission->shape).temperatureK, 2700);
    EXPECT_EQ(blackbody->emission->scale, 5);

    auto table =
        parse(R"({"emission": {"wavelengths": [350, 400], "values": [3, 0], "scale": 2}})");
    ASSERT_TRUE(table.ok()) << table.error().message;
    EXPECT_EQ(std::get<TabulatedSpectrum>(table->emission->shape).values,
              (std::vector<double>{3, 0}));
    EXPECT_EQ(table->emission->scale, 2);

    // Emission RGB may exceed 1 (it scales a bounded shape times D65).
    auto rgb = parse(R"({"emission": {"rgb": [4, 2, 0], "scale": 0}})");
    ASSERT_TRUE(rgb.ok()) << rgb.error().message;
    EXPECT_EQ(std::get<RgbSpectrum>(rgb->emission->shape).rgb, (std::array<double, 3>{4, 2, 0}));
    EXPECT_EQ(rgb->emission->scale, 0);

    auto gaussian = parse(R"({"emission": {"gaussian": {"peak": 365, "fwhm": 10}, "scale": 3}})");
    ASSERT_TRUE(gaussian.ok()) << gaussian.error().message;
    EXPECT_EQ(std::get<GaussianSpectrum>(gaussian->emission->shape).peakNm, 365);
    EXPECT_EQ(gaussian->emission->scale, 3);
}

TEST(MaterialExtension, FluorescencePreset) {
    auto extension = parse(R"({"fluorescence": {"preset": "Fluorescein"}})");
    ASSERT_TRUE(extension.ok()) << extension.error().message;
    EXPECT_EQ(std::get<FluorophorePreset>(*extension->fluorescence).name, "fluorescein");
    auto rhodamine = parse(R"({"fluorescence": {"preset": "RHODAMINE6G"}})");
    ASSERT_TRUE(rhodamine.ok()) << rhodamine.error().message;
    EXPECT_EQ(std::get<FluorophorePreset>(*rhodamine->fluorescence).name, "rhodamine6g");
}

TEST(MaterialExtension, FluorescenceParams) {
    auto extension = parse(R"({"fluorescence": {
        "absorption": {"gaussian": {"peak": 490, "fwhm": 30}, "scale": 0.6},
        "emission": {"wavelengths": [500, 515, 560], "values": [0, 1, 0.2]},
        "quantumYield": 0.9}})");
    ASSERT_TRUE(extension.ok()) << extension.error().message;
    const auto& params = std::get<FluorescenceParams>(*extension->fluorescence);
    EXPECT_EQ(std::get<GaussianSpectrum>(params.absorption.shape).peakNm, 490);
    EXPECT_EQ(params.absorption.scale, 0.6);
    EXPECT_EQ(std::get<TabulatedSpectrum>(params.emission.shape).values,
              (std::vector<double>{0, 1, 0.2}));
    EXPECT_EQ(params.quantumYield, 0.9);
}

TEST(MaterialExtension, FluorescenceMatrix) {
    // Columns sum to 0.75 + 0.25 = 1 (exactly the conservation limit), 0.5 + 0.25, 0.3.
    auto extension = parse(R"({"fluorescence": {"matrix": {"wavelengths": [400, 450, 500],
        "values": [[0.75, 0, 0], [0.125, 0.5, 0], [0.125, 0.25, 0.3]]}}})");
    ASSERT_TRUE(extension.ok()) << extension.error().message;
    const auto& matrix = std::get<FluorescenceMatrix>(*extension->fluorescence);
    EXPECT_EQ(matrix.wavelengthsNm, (std::vector<double>{400, 450, 500}));
    ASSERT_EQ(matrix.values.size(), 3u);
    EXPECT_EQ(matrix.values[2], (std::vector<double>{0.125, 0.25, 0.3}));
}

TEST(MaterialExtension, ValueRangeErrorsNameTheElement) {
    expectError(R"({"reflectance": {"wavelengths": [400, 450, 500, 550],
                    "values": [0.1, 0.2, 0.3, 1.2]}})",
                "reflectance.values[3]: 1.2 is outside [0, 1]");
    expectError(R"({"reflectance": {"rgb": [0.5, -0.1, 0]}})",
                "reflectance.rgb[1]: -0.1 is outside [0, 1]");
    expectError(R"({"emission": {"wavelengths": [400, 500], "values": [-1, 2]}})",
                "emission.values[0]: -1 is negative");
    expectError(R"({"emission": {"rgb": [1, 1, -2]}})", "emission.rgb[2]: -2 is negative");
    expectError(R"({"emission": {"preset": "D65", "scale": -1}})",
                "emission.scale: -1 is negative");
    // Shapes stay within [0, 1], so a reflectance scale over 1 could leave that range.
    expectError(R"({"reflectance": {"rgb": [1, 1, 1], "scale": 2}})",
                "reflectance.scale: 2 is outside [0, 1]");
    expectError(R"({"fluorescence": {"absorption": {"rgb": [1, 1, 1]},
                    "emission": {"rgb": [0, 0, 1], "scale": 0}, "quantumYield": 1}})",
                "fluorescence.emission.scale: 0 makes the fluorescence emission shape zero");
}

TEST(MaterialExtension, WavelengthErrors) {
    expectError(R"({"reflectance": {"wavelengths": [400, 500, 450], "values": [0, 0, 0]}})",
                "reflectance.wavelengths[2]: 450 nm does not follow 500 nm; wavelengths must be "
                "strictly ascending");
    expectError(R"({"reflectance": {"wavelengths": [400, 400], "values": [0, 0]}})",
                "reflectance.wavelengths[1]: 400 nm does not follow 400 nm; wavelengths must be "
                "strictly ascending");
    // The accepted range is [kMinWavelengthNm, kMaxWavelengthNm] = [200, 2500] nm.
    expectError(R"({"emission": {"wavelengths": [150, 500], "values": [1, 1]}})",
                "emission.wavelengths[0]: 150 nm is outside [200, 2500] nm");
    expectError(R"({"emission": {"wavelengths": [500], "values": [1]}})",
                "emission.wavelengths: needs at least 2 wavelengths, got 1");
    expectError(R"({"reflectance": {"wavelengths": [400, 450, 500], "values": [0, 0]}})",
                "reflectance.values: 2 values for 3 wavelengths; give one value per wavelength");
    expectError(R"({"reflectance": {"wavelengths": [400, 450]}})",
                "reflectance: 'wavelengths' given without 'values'");
}

TEST(MaterialExtension, TypeErrors) {
    EXPECT_EQ(errorOf("[1, 2]"), kWhere + ": expected an object, got array [1,2]");
    expectError(R"({"reflectance": {"wavelengths": [400, 500], "values": "abc"}})",
                "reflectance.values: expected an array of numbers, got string \"abc\"");
    expectError(R"({"reflectance": {"wavelengths": [400, 500], "values": [0.5, "x"]}})",
                "reflectance.values[1]: expected a number, got string \"x\"");
    expectError(R"({"reflectance": {"rgb": [0.5, 0.5]}})",
                "reflectance.rgb: expected an array of 3 numbers [r, g, b], got array [0.5,0.5]");
    expectError(R"({"emission": {"blackbody": "hot"}})",
                "emission.blackbody: expected a number, got string \"hot\"");
    expectError(R"({"emission": 5})", "emission: expected an object, got number 5");
    expectError(R"({"reflectance": {"rgb": [true, 0, 0]}})",
                "reflectance.rgb[0]: expected a number, got boolean true");

    // Built in memory, a JSON value can hold NaN (no file can).
    json object = {{"emission", {{"wavelengths", {400, 500}}, {"values", {1.0, NAN}}}}};
    EXPECT_EQ(errorOfJson(object), kWhere + ".emission.values[1]: nan is not finite");
}

TEST(MaterialExtension, UnknownMembersListTheAllowedOnes) {
    expectError(R"({"reflectence": {"rgb": [0, 0, 0]}})",
                "reflectence: unknown member; allowed: reflectance, emission, fluorescence");
    expectError(R"({"reflectance": {"wavelengths": [400, 500], "valeus": [0, 0]}})",
                "reflectance.valeus: unknown member; allowed: wavelengths, values, rgb, preset, "
                "blackbody, gaussian, scale");
    expectError(R"({"emission": {"gaussian": {"peak": 400, "width": 10}}})",
                "emission.gaussian.width: unknown member; allowed: peak, fwhm");
    expectError(R"({"fluorescence": {"preset": "neon", "yield": 1}})",
                "fluorescence.yield: unknown member; allowed: preset, absorption, emission, "
                "quantumYield, matrix");
}

TEST(MaterialExtension, ShapeCountErrors) {
    expectError(R"({"emission": {"rgb": [1, 1, 1], "preset": "D65"}})",
                "emission: gives both rgb and preset; a spectrum has exactly one shape");
    expectError(R"({"emission": {"scale": 2}})",
                "emission: no emission spectrum given; give one of wavelengths+values, rgb, "
                "preset, blackbody, gaussian");
}

TEST(MaterialExtension, PresetErrors) {
    expectError(R"({"reflectance": {"preset": "D65"}})",
                "reflectance.preset: reflectance cannot be an illuminant preset; use "
                "wavelengths+values, rgb or gaussian");
    expectError(R"({"reflectance": {"blackbody": 3000}})",
                "reflectance.blackbody: reflectance cannot be a blackbody; use "
                "wavelengths+values, rgb or gaussian");
    expectError(R"({"emission": {"preset": "sunlight"}})",
                "emission.preset: unknown illuminant preset 'sunlight'; known: " +
                    joinNames(illuminantPresetNames()));
    expectError(R"({"fluorescence": {"preset": "glowstick"}})",
                "fluorescence.preset: unknown fluorophore preset 'glowstick'; known: " +
                    joinNames(fluorophorePresetNames()));
    expectError(R"({"fluorescence": {"preset": 3}})",
                "fluorescence.preset: expected a fluorophore name, got number 3; known: " +
                    joinNames(fluorophorePresetNames()));
}

TEST(MaterialExtension, BlackbodyAndGaussianErrors) {
    expectError(R"({"emission": {"blackbody": 50}})",
                "emission.blackbody: 50 K is outside [100, 100000] K");
    expectError(R"({"emission": {"blackbody": 200000}})",
                "emission.blackbody: 200000 K is outside [100, 100000] K");
    expectError(R"({"emission": {"gaussian": {"peak": 100, "fwhm": 10}}})",
                "emission.gaussian.peak: 100 nm is outside [200, 2500] nm");
    expectError(R"({"emission": {"gaussian": {"peak": 400, "fwhm": 0}}})",
                "emission.gaussian.fwhm: 0 nm is not positive");
    expectError(R"({"emission": {"gaussian": {"peak": 400}}})",
                "emission.gaussian: 'fwhm' is missing");
}

TEST(MaterialExtension, FluorescenceParamErrors) {
    const std::string absorption = R"("absorption": {"gaussian": {"peak": 350, "fwhm": 20}})";
    const std::string emission = R"("emission": {"gaussian": {"peak": 435, "fwhm": 30}})";
    expectError("{\"fluorescence\": {" + absorption + ", " + emission + ", \"quantumYield\": 1.5}}",
                "fluorescence.quantumYield: 1.5 is outside [0, 1]");
    expectError("{\"fluorescence\": {" + absorption + ", " + emission + "}}",
                "fluorescence: 'quantumYield' is missing; absorption, emission and quantumYield "
                "are all required");
    expectError("{\"fluorescence\": {" + absorption + ", \"quantumYield\": 0.5}}",
                "fluorescence: 'emission' is missing; absorption, emission and quantumYield are "
                "all required");
    expectError(
        R"({"fluorescence": {"absorption": {"wavelengths": [300, 400], "values": [0.5, 1.5]},
                    "emission": {"rgb": [0, 0, 1]}, "quantumYield": 1}})",
        "fluorescence.absorption.values[1]: 1.5 is outside [0, 1]");
    expectError("{\"fluorescence\": {" + absorption +
                    R"(, "emission": {"wavelengths": [400, 500], "values": [0, 0]},
                    "quantumYield": 1}})",
                "fluorescence.emission.values: all values are 0; a fluorescence emission shape "
                "needs a non-zero value");
    expectError("{\"fluorescence\": {" + absorption +
                    R"(, "emission": {"wavelengths": [400, 500], "values": [1, -1]},
                    "quantumYield": 1}})",
                "fluorescence.emission.values[1]: -1 is negative");
    expectError(R"({"fluorescence": {"preset": "neon", "quantumYield": 1}})",
                "fluorescence: give only one of: preset; absorption + emission + quantumYield; "
                "matrix");
    expectError(R"({"fluorescence": {}})",
                "fluorescence: give one of: preset; absorption + emission + quantumYield; matrix");
}

TEST(MaterialExtension, MatrixErrors) {
    // values[0][2] moves light from 500 nm to 400 nm: against the Stokes shift (DESIGN.md 5).
    expectError(R"({"fluorescence": {"matrix": {"wavelengths": [400, 450, 500],
                    "values": [[0.5, 0, 0.1], [0, 0.5, 0], [0, 0, 0.5]]}}})",
                "fluorescence.matrix.values[0][2]: 0.1 would re-emit light from 500 nm at the "
                "shorter 400 nm; entries above the diagonal must be 0");
    // Column 0 sums to 0.75 + 0.45 = 1.2 > 1: more light out than in.
    expectError(R"({"fluorescence": {"matrix": {"wavelengths": [400, 450],
                    "values": [[0.75, 0], [0.45, 0.5]]}}})",
                "fluorescence.matrix.values: column 0 (400 nm) sums to 1.2, over 1: it would "
                "create energy");
    expectError(R"({"fluorescence": {"matrix": {"wavelengths": [400, 450],
                    "values": [[0.5, 0], [-0.1, 0.5]]}}})",
                "fluorescence.matrix.values[1][0]: -0.1 is negative");
    expectError(R"({"fluorescence": {"matrix": {"wavelengths": [400, 450],
                    "values": [[0.5, 0], [0.1]]}}})",
                "fluorescence.matrix.values[1]: expected 2 numbers, got array [0.1]");
    expectError(R"({"fluorescence": {"matrix": {"wavelengths": [400, 450, 500],
                    "values": [[0.5, 0, 0], [0.1, 0.5, 0]]}}})",
                "fluorescence.matrix.values: expected 3 rows of 3 numbers (one per "
                "wavelength), got array [[0.5,0,0],[0.1,0.5,0]]");
    expectError(R"({"fluorescence": {"matrix": {"wavelengths": [450, 400],
                    "values": [[0.5, 0], [0, 0.5]]}}})",
                "fluorescence.matrix.wavelengths[1]: 400 nm does not follow 450 nm; wavelengths "
                "must be strictly ascending");
    expectError(R"({"fluorescence": {"matrix": {"wavelengths": [400, 450]}}})",
                "fluorescence.matrix: 'values' is missing");
}

// materialExtensionToJson is parseMaterialExtension's inverse: every form parses back to an
// extension that writes the same JSON, numbers exact (0.1 + 0.2 keeps its last bit).
TEST(MaterialExtension, WritesWhatParsesBackExactly) {
    const char* forms[] = {
        R"({"reflectance": {"wavelengths": [400, 550.5, 700], "values": [0.1, 0.30000000000000004, 0.9]}})",
        R"({"reflectance": {"rgb": [0.25, 0.5, 0.75], "scale": 0.5}})",
        R"({"reflectance": {"gaussian": {"peak": 600, "fwhm": 80}}})",
        R"({"emission": {"preset": "blacklight", "scale": 2}})",
        R"({"emission": {"blackbody": 2700, "scale": 12.5}})",
        R"({"emission": {"rgb": [0, 0, 0], "scale": 0}})",
        R"({"fluorescence": {"preset": "fluorescein"}})",
        R"({"fluorescence": {"absorption": {"gaussian": {"peak": 365, "fwhm": 40}, "scale": 0.5},
            "emission": {"gaussian": {"peak": 450, "fwhm": 50}}, "quantumYield": 0.8}})",
        R"({"fluorescence": {"matrix": {"wavelengths": [350, 450], "values": [[0.5, 0], [0.25, 0.9]]}}})",
        R"({"fluorescence": null})",
    };
    for (const char* text : forms) {
        auto parsed = parse(text);
        ASSERT_TRUE(parsed) << text << ": " << parsed.error().message;
        const json written = materialExtensionToJson(*parsed);
        EXPECT_EQ(written, json::parse(text)) << text;
        auto again = parseMaterialExtension(written, kWhere);
        ASSERT_TRUE(again) << again.error().message;
        EXPECT_EQ(materialExtensionToJson(*again), written) << text;
    }
    // "fluorescence": null removes a material's fluorescence when overlaid.
    MaterialExtension fluorescent = *parse(R"({"fluorescence": {"preset": "neon"}})");
    mergeExtension(fluorescent, *parse(R"({"fluorescence": null})"));
    EXPECT_FALSE(fluorescent.fluorescence);
}

}  // namespace
}  // namespace daisy
