// The pair kernel (DESIGN.md section 8): one invocation per unordered pair of this dispatch. main()
// only unpacks ids and calls the shared pairEntry or pairEntryVisibility
// (src/shared/pair_kernel.h), the functions the reference backend runs on the CPU. Inputs are the
// push constants (PairKernelParams, gpu_types.h): buffer device addresses of the patches, the flat
// BVH and this batch's pairs and results.
//
// Two builds (cmake/Shaders.cmake variants): the plain one walks the flat BVH in the shader
// (bvh_traverse.h); "ray_query" (-DDAISY_RAY_QUERY, GL_EXT_ray_query) traces the shadow
// segments of the visibility pass through the device's acceleration structure (params.scene)
// instead, the same segments, span and weights (visibility.h DAISY_SEGMENT_OCCLUDED).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#ifdef DAISY_RAY_QUERY
#extension GL_EXT_ray_query : require
#extension GL_EXT_ray_flags_primitive_culling : require
#endif

#include "shared/config.h"
#include "shared/gpu_types.h"

layout(local_size_x = DAISY_PAIR_WORKGROUP_SIZE) in;

// Specialised per build (vulkan_backend.cpp): the method and the level fold to constants, so a
// pipeline holds only its method's kernel, and kMode picks the unoccluded factors
// (DAISY_PAIR_MODE_FACTORS, no BVH code), V_ij alone (DAISY_PAIR_MODE_VISIBILITY, no
// quadrature) or the hybrid factors without the refinement (DAISY_PAIR_MODE_FAR_FIELD). It
// matters on lavapipe, which runs both sides of every branch (masked SIMD).
layout(constant_id = 0) const int kMethod = DAISY_METHOD_HYBRID;
layout(constant_id = 1) const int kLevel = DAISY_DEFAULT_QUADRATURE_LEVEL;
layout(constant_id = 2) const int kMode = DAISY_PAIR_MODE_FACTORS;

layout(push_constant, scalar) uniform Push {
    PairKernelParams params;
};

#ifdef DAISY_RAY_QUERY
// True when some triangle of the acceleration structure crosses org + t dir at tmin <= t <= tmax
// (t in units of |dir|, both faces, any hit). The geometry is opaque, so one proceed step
// commits the first hit found, and gl_RayFlagsTerminateOnFirstHitEXT ends the traversal there.
bool rayQueryOccluded(vec3 org, vec3 dir, float tmin, float tmax) {
    rayQueryEXT query;
    rayQueryInitializeEXT(
        query, accelerationStructureEXT(params.scene),
        gl_RayFlagsOpaqueEXT | gl_RayFlagsTerminateOnFirstHitEXT | gl_RayFlagsSkipAABBEXT, 0xff,
        org, tmin, dir, tmax);
    rayQueryProceedEXT(query);
    return rayQueryGetIntersectionTypeEXT(query, true) != gl_RayQueryCommittedIntersectionNoneEXT;
}
#define DAISY_SEGMENT_OCCLUDED rayQueryOccluded
#endif

#include "shared/pair_kernel.h"

DAISY_BUFFER(KernelPatches, PatchGeometry);
DAISY_BUFFER(KernelPairs, PairIndex);
layout(buffer_reference, scalar, buffer_reference_align = 4) writeonly buffer KernelResults {
    PairFactors v[];
};

void main() {
    const uint k = gl_GlobalInvocationID.x;
    if (k >= params.pairCount) return;
    const uint slot = params.pairOffset + k;
    const PairIndex pair = KernelPairs(params.pairs).v[slot];
    KernelPatches patches = KernelPatches(params.patches);
    BvhNodeBuffer nodes = BvhNodeBuffer(params.nodes);
    BvhTriangleBuffer triangles = BvhTriangleBuffer(params.triangles);
    PairFactors f;
    if (kMode == DAISY_PAIR_MODE_VISIBILITY) {
        float v = pairEntryVisibility(pair.i, pair.j, patches.v[pair.i], patches.v[pair.j],
                                      params.rays, params.seed, params.clearance, nodes, triangles);
        f.fij = v;
        f.fji = v;
    } else if (kMode == DAISY_PAIR_MODE_FAR_FIELD) {
        f = pairEntryFarField(patches.v[pair.i], patches.v[pair.j], kLevel);
    } else {
        f = pairEntry(pair.i, pair.j, patches.v[pair.i], patches.v[pair.j], kMethod, kLevel, 0,
                      params.seed, params.clearance, nodes, triangles);
    }
    KernelResults(params.results).v[slot] = f;
}
