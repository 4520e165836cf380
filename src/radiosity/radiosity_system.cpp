#include "radiosity/radiosity_system.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "core/strings.h"
#include "spectral/spectrum.h"

namespace daisy {

std::vector<uint8_t> RadiositySystem::ownEmitters() const {
    std::vector<uint8_t> emits(patchCount, 0);
    for (std::size_t e = 0; e < emission.size(); ++e) {
        const double own = emission[e] - (punctualEmission.empty() ? 0.0 : punctualEmission[e]);
        if (own > 0) emits[e / wavelengthCount] = 1;
    }
    return emits;
}

bool RadiositySystem::hasFluorescence() const {
    return std::any_of(operators.begin(), operators.end(),
                       [](const MaterialOperator& op) { return !op.isDiagonal; });
}

void finishOperator(MaterialOperator& op, const std::vector<double>& binWidthsNm) {
    const std::size_t m = op.matrix.size;
    op.diagonal.assign(m, 0);
    op.isDiagonal = true;
    op.isZero = true;
    op.maxPowerGain = 0;
    for (std::size_t o = 0; o < m; ++o) {
        for (std::size_t k = 0; k < m; ++k) {
            const double value = op.matrix(o, k);
            if (value != 0) op.isZero = false;
            if (o != k && value != 0) op.isDiagonal = false;
        }
        op.diagonal[o] = op.matrix(o, o);
    }
    for (std::size_t k = 0; k < m; ++k) {
        double gain = 0;
        for (std::size_t o = 0; o < m; ++o)
            gain += op.matrix(o, k) * binWidthsNm[o] / binWidthsNm[k];
        op.maxPowerGain = std::max(op.maxPowerGain, gain);
    }
}

namespace {

constexpr double kAppearanceSteps = 4096;  // quantisation of patch means (operators shared)

double luminance(const std::array<double, 3>& rgb) {
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];  // Rec. 709 / sRGB Y weights
}

std::array<double, 3> quantised(const Rgb3& rgb, double high) {
    std::array<double, 3> out{};
    for (int c = 0; c < 3; ++c) {
        const double value = std::clamp(double(rgb[c]), 0.0, high);
        out[c] = std::round(value * kAppearanceSteps) / kAppearanceSteps;
    }
    return out;
}

// `base` with its reflectance (emission) RGB replaced by `rgb`; a spectral description in the
// extension keeps its shape, scaled by the luminance ratio.
Material withReflectance(const Material& base, const std::array<double, 3>& rgb) {
    Material material = base;
    if (material.spectral.reflectance) {
        const double from = luminance(base.baseColor);
        material.spectral.reflectance->scale *= from > 0 ? std::min(luminance(rgb) / from, 1.0) : 0;
    }
    material.baseColor = rgb;
    return material;
}

Material withEmission(const Material& base, const std::array<double, 3>& rgb) {
    Material material = base;
    if (material.spectral.emission) {
        const double from = luminance(base.emissiveRgb);
        material.spectral.emission->scale *= from > 0 ? luminance(rgb) / from : 0;
    }
    material.emissiveRgb = rgb;
    return material;
}

// Builds operators, deduplicated by their matrices.
class OperatorTable {
public:
    OperatorTable(RadiositySystem& system, const WavelengthSet& set) : system_(system), set_(set) {}

    Expected<uint32_t> operatorOf(const Material& material) {
        const std::string where = material.origin.empty() ? material.name : material.origin;
        auto matrix =
            materialReradiationMatrix(set_, material.spectral.reflectance, material.baseColor,
                                      material.spectral.fluorescence, where);
        if (!matrix) return matrix.error();
        auto [it, inserted] = byValues_.try_emplace(matrix->values, 0);
        if (inserted) {
            MaterialOperator op;
            op.matrix = std::move(*matrix);
            finishOperator(op, system_.binWidthsNm);
            system_.operators.push_back(std::move(op));
            it->second = static_cast<uint32_t>(system_.operators.size() - 1);
        }
        auto& names = system_.operators[it->second].materialNames;
        if (std::find(names.begin(), names.end(), material.name) == names.end())
            names.push_back(material.name);
        return it->second;
    }

private:
    RadiositySystem& system_;
    const WavelengthSet& set_;
    std::map<std::vector<double>, uint32_t> byValues_;
};

}  // namespace

Expected<RadiositySystem> buildRadiositySystem(const Scene& scene, const PatchMesh& patches,
                                               const WavelengthSet& set,
                                               const PatchAppearance* appearance) {
    RadiositySystem system;
    const std::size_t m = set.size();
    system.patchCount = static_cast<uint32_t>(patches.patchCount());
    system.wavelengthCount = m;
    system.wavelengthsNm = set.wavelengthsNm();
    system.binWidthsNm = set.binWidthsNm();
    system.areas = patches.areas;

    // Per scene material: its emission on the set and the operator it maps to (equal matrices
    // share one operator, so the solver touches as few distinct M as the scene has).
    OperatorTable table(system, set);
    std::vector<std::vector<double>> materialEmission(scene.materials.size());
    std::vector<uint32_t> materialOperator(scene.materials.size());
    for (std::size_t index = 0; index < scene.materials.size(); ++index) {
        const Material& material = scene.materials[index];
        const std::string where = material.origin.empty() ? material.name : material.origin;
        auto op = table.operatorOf(material);
        if (!op) return op.error();
        materialOperator[index] = *op;
        auto emission =
            daisy::materialEmission(set, material.spectral.emission, material.emissiveRgb, where);
        if (!emission) return emission.error();
        materialEmission[index] = std::move(*emission);
    }

    // Patch means of textured and vertex-coloured materials: (material, quantised RGB) ->
    // operator or emission.
    using Key = std::pair<uint32_t, std::array<double, 3>>;
    std::map<Key, uint32_t> patchOperators;
    std::map<Key, std::vector<double>> patchEmissions;
    const bool varies = appearance != nullptr && !appearance->empty() &&
        appearance->reflectanceVaries.size() == patches.patchCount();

    system.emission.assign(std::size_t(system.patchCount) * m, 0);
    system.patchOperator.resize(system.patchCount);
    for (uint32_t i = 0; i < system.patchCount; ++i) {
        const uint32_t material = patches.materials[i];
        if (material >= scene.materials.size()) {
            return Error{concat(scene.path, ": patch ", i, " uses material ", material,
                                " but the scene has ", scene.materials.size())};
        }
        system.patchOperator[i] = materialOperator[material];
        const std::vector<double>* emission = &materialEmission[material];
        if (varies && appearance->reflectanceVaries[i]) {
            const Key key{material, quantised(appearance->reflectance[i], 1.0)};
            auto it = patchOperators.find(key);
            if (it == patchOperators.end()) {
                auto op = table.operatorOf(withReflectance(scene.materials[material], key.second));
                if (!op) return op.error();
                it = patchOperators.emplace(key, *op).first;
            }
            system.patchOperator[i] = it->second;
        }
        if (varies && appearance->emissionVaries[i]) {
            const Key key{material, quantised(appearance->emission[i], 1e30)};
            auto it = patchEmissions.find(key);
            if (it == patchEmissions.end()) {
                const Material derived = withEmission(scene.materials[material], key.second);
                auto sampled = daisy::materialEmission(set, derived.spectral.emission,
                                                       derived.emissiveRgb, derived.origin);
                if (!sampled) return sampled.error();
                it = patchEmissions.emplace(key, std::move(*sampled)).first;
            }
            emission = &it->second;
        }
        std::copy(emission->begin(), emission->end(), system.emission.begin() + std::size_t(i) * m);
    }
    return system;
}

Expected<SceneSpectralFacts> sceneSpectralFacts(const Scene& scene) {
    SceneSpectralFacts facts;
    for (const Material& material : scene.materials) {
        if (material.isFluorescent()) facts.hasFluorescence = true;
        if (!material.isEmissive()) continue;
        const SpectrumSpec spec = material.spectral.emission
            ? *material.spectral.emission
            : SpectrumSpec{RgbSpectrum{material.emissiveRgb}, 1.0};
        auto uv = isUvEmitting(spec);
        if (!uv) return withContext(uv.error(), material.origin);
        if (*uv) facts.hasUvLights = true;
    }
    for (const PunctualLight& light : scene.lights) {
        if (!light.spectrum) continue;
        auto uv = isUvEmitting(*light.spectrum);
        if (!uv) return withContext(uv.error(), concat(scene.path, ": light '", light.name, "'"));
        if (*uv) facts.hasUvLights = true;
    }
    return facts;
}

}  // namespace daisy
