// The viewer's GPU-visible push constants and its false-colour ramp, read by C++ (src/viewer/)
// and the raster shaders (shaders/viewer_patches.*.glsl). Kept apart from gpu_types.h, whose
// structs need 64-bit integers: the viewer runs on any Vulkan 1.2 device, shaderInt64 or not.
#ifndef DAISY_SHARED_VIEWER_TYPES_H
#define DAISY_SHARED_VIEWER_TYPES_H

#include "prelude.h"

// What the fragment shader shows (ViewerPush.mode).
#define DAISY_VIEWER_MODE_COLOUR 0u  // value.xyz is CIE XYZ radiance: colourRows turn it to RGB
#define DAISY_VIEWER_MODE_FALSE 1u  // value.w is a scalar shown on the false-colour ramp
// ViewerPush.flags bits.
#define DAISY_VIEWER_FLAG_ENCODE_SRGB 1u  // the target is UNORM: apply the sRGB transfer curve
#define DAISY_VIEWER_FLAG_WIREFRAME 2u  // draw the patch edges over the shading
// The texture detail's sampled image (set 0), read by the shaders' texture_detail variant.
#define DAISY_VIEWER_DETAIL_BINDING 0

DAISY_SHARED_BEGIN

// Push constants of the patch pipeline, 128 bytes (Vulkan's guaranteed maxPushConstantsSize).
struct ViewerPush {
    float viewProj[16];  // clip from world (scene units), column-major, reverse-Z infinite far
    float colourRows[9];  // 3 rows of linear display RGB from XYZ radiance times the exposure
                          // scale (W^-1 m^2 sr nm)
    uint picked;  // the picked patch + 1, outlined and tinted; 0 = none
    float reserved[2];
    uint mode;  // DAISY_VIEWER_MODE_*
    uint flags;  // DAISY_VIEWER_FLAG_*
    float falseLo;  // log10 of the scalar at the ramp's start
    float falseHi;  // log10 of the scalar at the ramp's end (> falseLo)
};

// One channel of the ramp through five stops at t = 0, 1/4, 1/2, 3/4, 1 (clamped).
DAISY_HD float rampChannel(float t, float c0, float c1, float c2, float c3, float c4) {
    float x = t < 0.0f ? 0.0f : (t > 1.0f ? 4.0f : 4.0f * t);
    if (x < 1.0f) return c0 + (c1 - c0) * x;
    if (x < 2.0f) return c1 + (c2 - c1) * (x - 1.0f);
    if (x < 3.0f) return c2 + (c3 - c2) * (x - 2.0f);
    return c3 + (c4 - c3) * (x - 3.0f);
}

// The false-colour ramp, t in [0, 1] (clamped) -> sRGB-encoded display colour: matplotlib's
// viridis (van der Walt and Smith 2015) sampled at five stops, perceptually ordered and readable
// in grey.
DAISY_HD vec3 falseColour(float t) {
    return vec3(rampChannel(t, 0.267f, 0.229f, 0.128f, 0.369f, 0.993f),
                rampChannel(t, 0.005f, 0.322f, 0.567f, 0.789f, 0.906f),
                rampChannel(t, 0.329f, 0.546f, 0.551f, 0.383f, 0.144f));
}

DAISY_SHARED_END

#ifndef DAISY_GLSL
static_assert(sizeof(daisy::shared::ViewerPush) == 128);
static_assert(offsetof(daisy::shared::ViewerPush, colourRows) == 64);
static_assert(offsetof(daisy::shared::ViewerPush, picked) == 100);
static_assert(offsetof(daisy::shared::ViewerPush, mode) == 112);
static_assert(offsetof(daisy::shared::ViewerPush, falseHi) == 124);
#endif

#endif  // DAISY_SHARED_VIEWER_TYPES_H
