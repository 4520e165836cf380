#pragma once
// KHR_lights_punctual as direct sources: the lights' direct irradiance on every
// patch, with visibility, reflected once into the emission term, E_i += M_i H_i, so the
// radiosity solve carries every later bounce. Units follow scene.h's PunctualLight: a light of
// colour c and intensity I (candela) at distance d gives the irradiance c I cos(theta) / d^2 as
// an RGB emission spectrum (the scale of emissive surfaces); a directional light (lux), c I cos.
// The spot cone and the range window are KHR_lights_punctual's recommended falloffs.
#include <cstddef>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "radiosity/radiosity_system.h"
#include "scene/scene.h"
#include "spectral/wavelength_set.h"

namespace daisy {

// Per patch and light, the factor g with H = g c I: V cos(theta) falloff / d^2 (m^-2) for point
// and spot lights, V cos(theta) for directional ones, V the unblocked fraction of shadow rays
// from 4 points on the patch (its centroid and the midpoints towards its corners).
struct LightGeometry {
    std::size_t lightCount = 0;
    std::vector<double> factors;  // patchCount x lightCount, row-major
};

// Traces the shadow rays. Errors when the ray caster cannot build the scene.
Expected<LightGeometry> punctualLightGeometry(const PatchMesh& patches,
                                              const std::vector<PunctualLight>& lights);

// The spot and range falloff of KHR_lights_punctual at `distance` and angle cosine
// `cosFromAxis` (between the spot's axis and the direction to the point); 1 for a point light
// without range.
double punctualFalloff(const PunctualLight& light, double distance, double cosFromAxis);

// Adds M_i H_i to system.emission for every patch. `lights` are the ones `geometry` was traced
// for.
Expected<void> addDirectLight(RadiositySystem& system, const LightGeometry& geometry,
                              const std::vector<PunctualLight>& lights, const WavelengthSet& set);

}  // namespace daisy
