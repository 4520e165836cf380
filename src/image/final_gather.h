#pragma once
// Final gathering at render time: the light the emitters put directly on each pixel's
// surface point is computed per sample, exactly, instead of being read from the patches' smooth
// radiosity, so shadows and penumbrae are as sharp as the geometry makes them.
//
// Split of the solved radiosity (DESIGN.md section 2): B_i = E_i + M_i P_i + M_i G_i with E_i
// what the patch emits, P_i the punctual lights' direct irradiance (its patch mean, exact by
// solid angle: radiosity/punctual_lights.h; the solve carries it in the emission term),
// G_i = sum_j F_ij B_j, and the direct part of G_i is D_i = sum_{j emitting} F_ij E_j. The
// image is
//     L(x) = [E + M (G - D)]_i / pi smoothed over vertices (vertex_radiance.h)
//          + M_i [H(x) + P(x)] / pi,   H(x) = sum_{lights l} E_l F(x -> l) V(x, l),
// F(x -> l) the exact point-to-triangle factor of each emitting source triangle (Lambert's
// contour formula, shared/formfactor.h, clipped to x's front half-space) and V(x, l) the
// visibility; P(x) each punctual light's c I cos(theta) falloff / d^2 at x behind one shadow
// segment (punctualPointFactor), as the path tracer's next-event estimation has it. Left in
// the smooth part, a point light 0.25 m from a wall made a disc of the patches' means:
// 10-15% too bright around the light's foot point and too dark at it. The lights are the emitting
// source triangles with each flat convex face of one emission merged into a fan over its outline
// (image/emitter_lights.h: the tubes' 176 triangles are 20 lights), which changes no factor.
//
// V from k shadow segments per sample, drawn over the lights in proportion to F(x -> l) times l's
// power (stratified over that distribution: a scene of two light triangles gives each k / 2, the
// black-light tubes' 20 lights get them by contribution) to stratified points on the chosen
// triangle. The segments to l give V_l = sum G open / sum G, G = cos_x cos_l / r^2 at each
// point: the points are uniform in area, the visible share weighs them by the kernel (a ratio
// estimator: consistent, exact when all are open or all blocked; an area-weighted fraction was
// 2% bright under a large half-hidden source, tests/render/final_gather_test.cpp).
// - Up to 32 lights every F_l is exact (SIMD lanes, radiosity/hybrid_far_field.h) and
//   H = sum_l E_l F_l V_l, a light that drew no segment taking the pooled open fraction of the
//   sample's segments: exact wherever every segment is open, or every one blocked, whatever the
//   lights' spectra.
// - Over 32, the draw uses a cheap point-source stand-in for F and each light's segments carry
//   its exact F over that stand-in (importance sampling, not exact where unoccluded).
//
// Penumbra refinement: the variance is where a light is partly hidden, so a first pass takes
// K / 16 segments a pixel (K over 32 lights, where unoccluded pixels vary too) and marks, per
// light, whether its segments were open or blocked; a second pass gives each pixel whose 8
// neighbours' marks hold both for one light the other 15 K / 16 (3 K over 32 lights), with
// fresh points, and averages the passes by segment count. Over 32 lights a penumbra pixel
// takes 4 K in all: the segments spread over many lights, each estimating its own visibility
// (the generator's interior, 200 light triangles, most of them its lamps' discs, and every
// light seen through an opening: 4.4% relative RMS luminance from its image at 1,024
// segments a penumbra pixel with 16 and 64, 1.9% with 64 and 256). A pixel's own marks never select
// it, so its first-pass value is independent of its selection. On the Cornell box this and the
// kernel weighting take the error against the path tracer from 2.05% to 1.56% (colored_lights 3.01%
// to 2.22%) for a few tenths of a second (docs/rendering.md). Deterministic: the points come from a
// hash of (seed, pass, pixel, sample, light), so the image has no noise from run to run.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/cancel.h"
#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "image/image.h"
#include "image/near_field.h"
#include "image/renderer.h"
#include "radiosity/radiosity_system.h"
#include "radiosity/transport.h"
#include "scene/scene.h"
#include "spectral/wavelength_set.h"

namespace daisy {

struct DirectLightSettings {
    // K shadow segments per penumbra pixel over all lights (4 K over 32 lights); every other
    // pixel takes max(1, K / 16) (K over 32 lights). Shared out over the pixel's samples
    // (ceil(count / samples) each, at least 1).
    int shadowRays = 64;
    uint32_t seed = 1;
};

// What the patches emit themselves (n x m, the system's layout): E without the punctual lights'
// direct light M_i P_i, which the patches reflect and the gather computes per sample.
std::vector<double> ownEmission(const RadiositySystem& system);

// B with the direct light removed: E_i + M_i (G_i - D_i) = B_i - M_i D_i - M_i P_i (n x m,
// row-major, the system's layout), D_i the emitters' light gathered through `transport`; for
// the patches marked in `patches` only (empty: all), the others keep B_i.
std::vector<double> radiosityWithoutDirectLight(const RadiositySystem& system,
                                                const Transport& transport,
                                                std::span<const double> radiosity,
                                                std::span<const uint8_t> patches = {});

// H at each patch's centroid (n x m, the system's layout; 0 for patches that reflect nothing):
// the estimate above with `direct.shadowRays` segments a patch, without F. The viewer's picture
// B = E + M H while F is being made. Stops early (the rest 0) when `cancel` is cancelled.
Expected<std::vector<double>> patchDirectIrradiance(const Scene& scene, const PatchMesh& patches,
                                                    const RadiositySystem& system,
                                                    const DirectLightSettings& direct,
                                                    const CancelToken* cancel = nullptr);

// The direct term M_i H(x) / pi per pixel, on the renderer's sample positions (stratum centres,
// image/pixel_samples.h, per pixel settings.pixelSides when given: edge_sampling.h) and box
// filter, in the channels of pipeline/channel_layout.h (coverage 0).
// Lights are the emitting triangles of scene.mesh, faces merged (emitter_lights.h), and
// scene.lights (KHR_lights_punctual). Fails (no
// crash) on what renderCornerValues refuses. `shader` (renderCornerValues's) moves hits to back
// patches and puts the texture detail on each sample's direct light. With `nearField`, each
// sample's irradiance also takes its near-field indirect part Near(x) (near_field.h).
Expected<Image> renderDirectLight(const Scene& scene, const PatchMesh& patches,
                                  const RadiositySystem& system, const WavelengthSet& set,
                                  const Camera& camera, const RenderSettings& settings,
                                  const DirectLightSettings& direct, bool spectral,
                                  const SampleShader* shader = nullptr,
                                  const NearField* nearField = nullptr);

}  // namespace daisy
