#include "radiosity/radiosity_system.h"

#include <algorithm>

#include "core/strings.h"
#include "spectral/spectrum.h"

namespace daisy {

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

Expected<RadiositySystem> buildRadiositySystem(const Scene& scene, const PatchMesh& patches,
                                               const WavelengthSet& set) {
    RadiositySystem system;
    const std::size_t m = set.size();
    system.patchCount = static_cast<uint32_t>(patches.patchCount());
    system.wavelengthCount = m;
    system.wavelengthsNm = set.wavelengthsNm();
    system.binWidthsNm = set.binWidthsNm();
    system.areas = patches.areas;

    // Per scene material: its emission on the set and the operator it maps to (equal matrices
    // share one operator, so the solver touches as few distinct M as the scene has).
    std::vector<std::vector<double>> materialEmission(scene.materials.size());
    std::vector<uint32_t> materialOperator(scene.materials.size());
    for (std::size_t index = 0; index < scene.materials.size(); ++index) {
        const Material& material = scene.materials[index];
        const std::string where = material.origin.empty() ? material.name : material.origin;
        auto matrix =
            materialReradiationMatrix(set, material.spectral.reflectance, material.baseColor,
                                      material.spectral.fluorescence, where);
        if (!matrix) return matrix.error();
        auto emission =
            daisy::materialEmission(set, material.spectral.emission, material.emissiveRgb, where);
        if (!emission) return emission.error();
        materialEmission[index] = std::move(*emission);

        auto same = std::find_if(
            system.operators.begin(), system.operators.end(),
            [&](const MaterialOperator& op) { return op.matrix.values == matrix->values; });
        if (same == system.operators.end()) {
            MaterialOperator op;
            op.matrix = std::move(*matrix);
            finishOperator(op, system.binWidthsNm);
            system.operators.push_back(std::move(op));
            same = system.operators.end() - 1;
        }
        same->materialNames.push_back(material.name);
        materialOperator[index] = static_cast<uint32_t>(same - system.operators.begin());
    }

    system.emission.assign(std::size_t(system.patchCount) * m, 0);
    system.patchOperator.resize(system.patchCount);
    for (uint32_t i = 0; i < system.patchCount; ++i) {
        const uint32_t material = patches.materials[i];
        if (material >= scene.materials.size()) {
            return Error{concat(scene.path, ": patch ", i, " uses material ", material,
                                " but the scene has ", scene.materials.size())};
        }
        system.patchOperator[i] = materialOperator[material];
        std::copy(materialEmission[material].begin(), materialEmission[material].end(),
                  system.emission.begin() + std::size_t(i) * m);
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
    return facts;
}

}  // namespace daisy
