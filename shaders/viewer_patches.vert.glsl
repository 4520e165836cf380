#version 450
// The viewer's patches (src/viewer/patch_renderer.h): three vertices per patch, in patch order,
// each with its corner's display value; the barycentric corner feeds the wireframe. The
// texture_detail variant (-DDAISY_TEXTURE_DETAIL) also passes on the texture detail's uv and factor
// (src/viewer/detail_vertices.h).
#extension GL_GOOGLE_include_directive : require
#include "shared/viewer_types.h"

layout(push_constant) uniform Push {
    ViewerPush p;
};

layout(location = 0) in vec4 inPosition;  // w: 1 on a double-sided surface
layout(location = 1) in vec4 inValue;
layout(location = 0) out vec4 outValue;
layout(location = 1) out vec3 outBarycentric;
layout(location = 2) flat out float outTwoSided;
layout(location = 3) flat out uint outPicked;  // 1 on the picked patch
#ifdef DAISY_TEXTURE_DETAIL
layout(location = 2) in vec2 inUv;
layout(location = 3) in vec3 inFactor;
layout(location = 4) out vec2 outUv;
layout(location = 5) out vec3 outFactor;
#endif

void main() {
    mat4 viewProj;
    for (int c = 0; c < 4; ++c)
        viewProj[c] = vec4(p.viewProj[4 * c], p.viewProj[4 * c + 1], p.viewProj[4 * c + 2],
                           p.viewProj[4 * c + 3]);
    gl_Position = viewProj * vec4(inPosition.xyz, 1.0);
    outTwoSided = inPosition.w;
    outValue = inValue;
#ifdef DAISY_TEXTURE_DETAIL
    outUv = inUv;
    outFactor = inFactor;
#endif
    outPicked = uint(gl_VertexIndex / 3) + 1u == p.picked ? 1u : 0u;
    int corner = gl_VertexIndex % 3;
    outBarycentric =
        vec3(corner == 0 ? 1.0 : 0.0, corner == 1 ? 1.0 : 0.0, corner == 2 ? 1.0 : 0.0);
}
