#version 450
// The viewer's patches: XYZ radiance -> exposed linear RGB -> clip -> sRGB curve (the same steps
// as daisy render's PNG, src/image/exposure.h), or a scalar on the false-colour ramp; optional
// wireframe edges. The texture_detail variant (-DDAISY_TEXTURE_DETAIL) multiplies the colour view's
// linear RGB by texel x factor per channel, `daisy render`'s texel / patch mean
// (src/image/texture_detail.h; the factor from src/viewer/detail_vertices.h, negative: ratio 1).
#extension GL_GOOGLE_include_directive : require
#include "shared/viewer_types.h"

layout(push_constant) uniform Push {
    ViewerPush p;
};

layout(location = 0) in vec4 inValue;
layout(location = 1) in vec3 inBarycentric;
layout(location = 2) flat in float inTwoSided;
layout(location = 3) flat in uint inPicked;
layout(location = 0) out vec4 outColour;
#ifdef DAISY_TEXTURE_DETAIL
layout(location = 4) in vec2 inUv;
layout(location = 5) in vec3 inFactor;
layout(set = 0, binding = DAISY_VIEWER_DETAIL_BINDING) uniform sampler2D detailTexture;
#endif

// IEC 61966-2-1 transfer curve, and its inverse.
float encodeSrgb(float c) {
    return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}
float decodeSrgb(float c) {
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

void main() {
    // Of a double-sided surface's two coincident patches, only the one facing the camera.
    if (inTwoSided > 0.5 && !gl_FrontFacing) discard;
    // The back of a one-sided surface neither emits nor reflects: black, as daisy render has it.
    bool oneSidedBack = !gl_FrontFacing;
    bool encode = (p.flags & DAISY_VIEWER_FLAG_ENCODE_SRGB) != 0u;
    vec3 display;
    if (p.mode == DAISY_VIEWER_MODE_FALSE) {
        float value = log(max(inValue.w, 1e-30)) / log(10.0);
        display =
            oneSidedBack ? vec3(0.0) : falseColour((value - p.falseLo) / (p.falseHi - p.falseLo));
        if (!encode)
            display = vec3(decodeSrgb(display.x), decodeSrgb(display.y), decodeSrgb(display.z));
    } else {
        vec3 xyz = oneSidedBack ? vec3(0.0) : inValue.xyz;
        vec3 rgb = vec3(dot(vec3(p.colourRows[0], p.colourRows[1], p.colourRows[2]), xyz),
                        dot(vec3(p.colourRows[3], p.colourRows[4], p.colourRows[5]), xyz),
                        dot(vec3(p.colourRows[6], p.colourRows[7], p.colourRows[8]), xyz));
#ifdef DAISY_TEXTURE_DETAIL
        vec3 texel = textureLod(detailTexture, inUv, 0.0).rgb;
        rgb *= vec3(inFactor.x < 0.0 ? 1.0 : inFactor.x * texel.x,
                    inFactor.y < 0.0 ? 1.0 : inFactor.y * texel.y,
                    inFactor.z < 0.0 ? 1.0 : inFactor.z * texel.z);
#endif
        rgb = clamp(rgb, vec3(0.0), vec3(1.0));
        display = encode ? vec3(encodeSrgb(rgb.x), encodeSrgb(rgb.y), encodeSrgb(rgb.z)) : rgb;
    }
    if ((p.flags & DAISY_VIEWER_FLAG_WIREFRAME) != 0u) {
        vec3 width = fwidth(inBarycentric);
        vec3 edge = smoothstep(vec3(0.0), 1.5 * width, inBarycentric);
        float inside = min(edge.x, min(edge.y, edge.z));
        display = mix(vec3(1.0, 0.55, 0.1), display, inside);
    }
    if (inPicked != 0u) {
        // The picked patch: tinted, with a thick cyan outline.
        vec3 width = fwidth(inBarycentric);
        vec3 edge = smoothstep(vec3(0.0), 3.0 * width, inBarycentric);
        float inside = min(edge.x, min(edge.y, edge.z));
        display = mix(vec3(0.1, 0.9, 1.0), mix(display, vec3(0.1, 0.9, 1.0), 0.25), inside);
    }
    outColour = vec4(display, 1.0);
}
