#pragma once
// KHR_lights_punctual as direct sources: the lights' direct irradiance on every
// patch, with visibility, reflected once into the emission term, E_i += M_i H_i, so the
// radiosity solve carries every later bounce. Units follow scene.h's PunctualLight: a light of
// colour c and intensity I (candela) puts the flux c I Omega on a surface it sees under the solid
// angle Omega (the irradiance c I cos(theta) / d^2 far away), as an RGB emission spectrum (the
// scale of emissive surfaces); a directional light (lux) the irradiance c I cos(theta).
// The spot cone and the range window are KHR_lights_punctual's recommended falloffs.
#include <array>
#include <cstddef>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "radiosity/radiosity_system.h"
#include "scene/scene.h"
#include "spectral/wavelength_set.h"

namespace daisy {

using Triangle3d = std::array<Vec3d, 3>;

// Per patch and light, the factor g with H = g c I, H the patch's mean irradiance. The patch's
// midpoint subdivision makes 4 regions, each seen through one shadow segment from a point of
// it, uniform in area from a hash of the patch and the region (deterministic; fixed points such
// as the regions' centroids fall into the same gaps of a regular grid together); g sums the
// open regions':
// point and spot lights punctualTriangleFlux / area (m^-2, cos(theta) falloff / d^2 far away,
// never more than the region's solid angle over the area however close the light), directional
// ones cos(theta) / 4.
struct LightGeometry {
    std::size_t lightCount = 0;
    std::vector<double> factors;  // patchCount x lightCount, row-major
};

// Traces the shadow rays. Errors when the ray caster cannot build the scene.
Expected<LightGeometry> punctualLightGeometry(const PatchMesh& patches,
                                              const std::vector<PunctualLight>& lights);

// The solid angle (sr) under which `from` sees the triangle t (counter-clockwise about its unit
// normal n), when `from` lies in front of t's plane; 0 when it lies behind or in it. Van Oosterom &
// Strackee 1983, "The solid angle of a plane triangle" (IEEE Trans. Biomed. Eng. 30(2)); from
// closer than t's longest edge, over its foot point near t, the same angle summed in closed form
// over the wedges between the foot point and t's edges, accurate to rounding however low the
// point (2 pi over the inside as the height goes to 0, pi on an edge).
double frontSolidAngle(const Vec3d& from, const Triangle3d& t, const Vec3d& n);

// The flux a point or spot light of unit intensity puts on the unoccluded triangle t (normal
// n), in W per W sr^-1: the integral of the falloff over the directions from the light to t's
// front, exactly frontSolidAngle without falloff, and with it at most that (the falloff's mean
// by quadrature: around the light's foot point on t's plane when the light is closer than t's
// size, else over 16 sub-triangles weighted by their solid angles).
double punctualTriangleFlux(const PunctualLight& light, const Triangle3d& t, const Vec3d& n);

// The spot and range falloff of KHR_lights_punctual at `distance` and angle cosine
// `cosFromAxis` (between the spot's axis and the direction to the point); 1 for a point light
// without range.
double punctualFalloff(const PunctualLight& light, double distance, double cosFromAxis);

// The irradiance factor g at point x (unit normal n) from `light`, H = g c I as above:
// cos(theta) falloff / d^2 for a point or spot light, cos(theta) for a directional one; 0 when
// the light lies behind x's surface or g is not finite (a light too close for d^3 to be a
// normal double). `shadowEnd` is set to where x's shadow segment ends: the light, or `far`
// (a length that leaves the scene) towards a directional light. The path tracer's next-event
// estimation and the final gather's per-sample direct light.
double punctualPointFactor(const PunctualLight& light, const Vec3d& x, const Vec3d& n, double far,
                           Vec3d& shadowEnd);

// A length that leaves the scene of `patches` from anywhere in it: four times its bounds'
// diagonal (the far end of a segment towards a directional light).
double leavingLength(const PatchMesh& patches);

// Per light, its irradiance spectrum at g = 1 on `set`: colour x intensity as an RGB emission
// spectrum, or its own spectral emission times the intensity. Fails naming the light on a
// spectrum that cannot be sampled.
Expected<std::vector<std::vector<double>>> punctualLightSpectra(
    const std::vector<PunctualLight>& lights, const WavelengthSet& set);

// Adds M_i H_i to system.emission for every patch. `lights` are the ones `geometry` was traced
// for.
Expected<void> addDirectLight(RadiositySystem& system, const LightGeometry& geometry,
                              const std::vector<PunctualLight>& lights, const WavelengthSet& set);

}  // namespace daisy
