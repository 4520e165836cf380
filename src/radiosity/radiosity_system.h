#pragma once
// The data of the radiosity equation (DESIGN.md sections 2, 5 and 6) apart from F:
//     B_i[o] = E_i[o] + sum_k M_mat(i)[o][k] G_i[k],   G_i = sum_j F_ij B_j,
// with E per patch (n x m, row-major) and the re-radiation matrix M stored once per distinct
// material operator, not per patch. Units: E and B are spectral radiant exitance
// (W m^-2 nm^-1) at the wavelength set's samples; areas in scene units squared.
#include <cstdint>
#include <string>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "scene/scene.h"
#include "scene/surface_appearance.h"
#include "spectral/fluorescence.h"
#include "spectral/wavelength_set.h"

namespace daisy {

// One distinct re-radiation matrix and what the solver needs to know about it.
struct MaterialOperator {
    ReradiationMatrix matrix;  // m x m, density to density (fluorescence.h)
    std::vector<double> diagonal;  // M[k][k], the reflectance at each sample
    bool isDiagonal = true;  // no fluorescence: M = diag(rho), wavelengths independent
    bool isZero = false;  // rho = 0 everywhere and no fluorescence: B_i = E_i, no gather
    // max_k of the power column sum c_k (fluorescence.h): energy out per energy in, at worst.
    double maxPowerGain = 0;
    std::vector<std::string> materialNames;  // the scene materials sharing this operator
};

struct RadiositySystem {
    uint32_t patchCount = 0;
    std::size_t wavelengthCount = 0;  // m
    std::vector<double> wavelengthsNm;  // m sample wavelengths
    std::vector<double> binWidthsNm;  // m weights: power = sum_k value_k * binWidthNm_k
    std::vector<double> emission;  // E, patchCount x m, row-major
    // The part of `emission` that is punctual lights' direct light reflected once, M_i H_i
    // (radiosity/punctual_lights.h), laid out as `emission`; empty when no light adds any. The
    // rest is what the surfaces emit themselves: the final gather's light sources.
    std::vector<double> punctualEmission;
    std::vector<double> areas;  // per patch
    std::vector<uint32_t> patchOperator;  // per patch: index into operators
    std::vector<MaterialOperator> operators;

    bool hasFluorescence() const;  // any operator with off-diagonal entries
    // Per patch, 1 when it emits light of its own: E beyond the punctual lights' share.
    std::vector<uint8_t> ownEmitters() const;
    const double* emissionRow(uint32_t patch) const {
        return emission.data() + patch * wavelengthCount;
    }
};

// Builds the system for `patches` (material indices into scene.materials) on `set`: samples
// every material's emission (spectral.h bin averages) and its re-radiation matrix, merges
// materials whose matrices are equal into one operator. Errors name the material (origin).
// With `appearance` (scene/surface_appearance.h), a patch whose reflectance or emission varies
// over its material (textures, vertex colours) takes its own mean: the material with that RGB
// (a spectral reflectance or emission scaled by the luminance ratio), quantised to 1/4096 so
// equal means share an operator.
Expected<RadiositySystem> buildRadiositySystem(const Scene& scene, const PatchMesh& patches,
                                               const WavelengthSet& set,
                                               const PatchAppearance* appearance = nullptr);

// Fills the derived fields of `op` (diagonal, isDiagonal, isZero, maxPowerGain) from its
// matrix and the set's bin widths; for systems assembled by hand (tests, benchmarks).
void finishOperator(MaterialOperator& op, const std::vector<double>& binWidthsNm);

// out = add + M in for one operator (m-vectors; add = null: out = M in): diagonal[o] in[o], or
// the lower-triangular sum over k <= o of M[o][k] in[k] (re-radiation only moves light to
// longer wavelengths), summed in that order and then added to add[o]. Every product of a
// re-radiation matrix with a vector goes through here (the solvers' B = E + M G too).
inline void applyOperator(const MaterialOperator& op, const double* in, double* out,
                          const double* add = nullptr) {
    const std::size_t m = op.matrix.size;
    if (op.isZero) {
        for (std::size_t o = 0; o < m; ++o)
            out[o] = add ? add[o] : 0.0;
    } else if (op.isDiagonal) {
        for (std::size_t o = 0; o < m; ++o)
            out[o] = add ? add[o] + op.diagonal[o] * in[o] : op.diagonal[o] * in[o];
    } else {
        for (std::size_t o = 0; o < m; ++o) {
            const double* row = op.matrix.values.data() + o * m;
            double sum = 0;
            for (std::size_t k = 0; k <= o; ++k)
                sum += row[k] * in[k];
            out[o] = add ? add[o] + sum : sum;
        }
    }
}

// out += M^T in (m-vectors): the adjoint, carrying importance from the re-emitted wavelength o
// back to the absorbed k (the path tracer's throughput).
inline void addTransposedOperator(const MaterialOperator& op, const double* in, double* out) {
    const std::size_t m = op.matrix.size;
    for (std::size_t o = 0; o < m; ++o) {
        if (in[o] == 0) continue;
        const double* row = op.matrix.values.data() + o * m;
        for (std::size_t k = 0; k <= o; ++k)
            out[k] += in[o] * row[k];
    }
}

// The two scene facts the `auto` wavelength set depends on (wavelength_set.h): some material
// (or punctual light with a spectrum) emits mostly UV, and some material is fluorescent.
struct SceneSpectralFacts {
    bool hasUvLights = false;
    bool hasFluorescence = false;
};
Expected<SceneSpectralFacts> sceneSpectralFacts(const Scene& scene);

}  // namespace daisy
