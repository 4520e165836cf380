#pragma once
// The independent reference: a spectral path tracer of the same scene model as the
// radiosity pipeline, sharing none of its light transport (no F, no solver, no vertex radiance).
// Surfaces are Lambertian reflectors/emitters on their geometric (front) normal, as in the
// radiosity model (DESIGN.md section 2): the back face of a one-sided surface neither emits nor
// reflects; a double-sided material's (glTF doubleSided) back face is its back patch
// (PatchMesh::backPatch), reflecting and emitting as the front does. Wavelengths
// are the set's samples, all m carried along each path; a surface applies its whole
// re-radiation matrix M (fluorescence.h) to the path's throughput, so fluorescence moves light
// between samples exactly as the radiosity equation does, without sampling a wavelength.
//
// Estimator (Kajiya 1986, the rendering equation, with next-event estimation): at each hit x,
// L_o[o] = E[o] / pi + (1 / pi) sum_k M[o][k] H[k], H the irradiance; direct H from an emitter
// point y sampled by power, E_y[k] / pi * cos_x cos_y / r^2 / pdf_area(y) behind a shadow ray;
// indirect H by one cosine-weighted ray (pdf cos / pi, so H ~ pi L_in). An emitter both
// techniques can reach is weighted by the power heuristic (multiple importance sampling, Veach &
// Guibas 1995), which keeps receivers close to a light (r^2 -> 0) from firefly noise. Punctual
// lights (KHR_lights_punctual, delta lights no ray can hit) add their irradiance c I cos falloff /
// d^2 (directional: c I cos) at every vertex behind a shadow ray, the same light
// radiosity/punctual_lights.h integrates over each patch. Russian
// roulette after three bounces. Pixel samples are stratified jittered (pixel_samples.h), box
// filter. Randomness is counter-based on (seed, pixel, sample, dimension): deterministic in any
// thread order.
#include <cstdint>

#include "core/cancel.h"
#include "core/expected.h"
#include "image/image.h"
#include "scene/scene.h"
#include "spectral/wavelength_set.h"

namespace daisy {

struct PathTraceSettings {
    int width = 640;
    int height = 480;
    int samplesPerPixel = 64;
    int maxBounces = 64;  // hard cap on path length (Russian roulette ends paths long before)
    uint32_t seed = 1;
    int threads = 0;  // 0 = all hardware threads
    bool spectral = false;  // also the m radiance channels (the renderer's spectral layout)
    bool showProgress = true;  // the terminal progress line (core/progress.h)
};

struct PathTraceResult {
    // Per pixel: [L_0 .. L_{m-1} when spectral] X Y Z coverage, the layout of
    // Session::patchChannels (radiance W m^-2 sr^-1 nm^-1, XYZ of it, coverage = fraction of
    // the pixel's samples that hit a surface).
    Image image;
    // Per pixel, one channel: the variance of the pixel's mean Y (sample variance / n), the
    // estimator's own noise.
    Image varianceY;
    // sqrt(mean variance) / mean Y over pixels with coverage > 0: the image's relative RMS noise.
    double relativeNoise = 0;
    uint64_t paths = 0;
    uint64_t rays = 0;  // closest-hit and shadow rays
    double seconds = 0;
    bool cancelled = false;
};

// Path traces `scene` (its materials sampled on `set`) through `camera`. Fails (no crash) on a
// bad size or sample count, a material that cannot be sampled, a camera outside float32 range,
// or when the ray caster cannot build the scene. A cancelled run returns what it has,
// cancelled = true.
Expected<PathTraceResult> pathTrace(const Scene& scene, const WavelengthSet& set,
                                    const Camera& camera, const PathTraceSettings& settings,
                                    const CancelToken* cancel = nullptr);

// sqrt(mean variance) / mean Y of `image` (the layout above, XYZ at channel yChannel - 1) over
// the pixels where mask (one value per pixel, may be empty = all covered pixels) is nonzero.
double relativeRmsNoise(const Image& image, int yChannel, const Image& varianceY,
                        const std::vector<uint8_t>& mask = {});

}  // namespace daisy
