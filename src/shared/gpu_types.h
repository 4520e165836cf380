// GPU-visible structs (STYLE.md rule 3): defined once here, scalar layout
// (GL_EXT_scalar_block_layout: vec3 is 12 bytes, 4-byte aligned), explicit named padding, units
// per field, and size/offset static_asserts in C++. Plus the few builders and predicates that
// belong to a struct.
#ifndef DAISY_SHARED_GPU_TYPES_H
#define DAISY_SHARED_GPU_TYPES_H

#include "prelude.h"

DAISY_SHARED_BEGIN

// One radiosity patch (a triangle) as the form-factor kernels see it. Corners counter-clockwise
// about `normal`. Build with makePatchGeometry, or fill normal and area from the double-precision
// PatchMesh values (same meaning). 64 bytes.
struct PatchGeometry {
    vec3 a;  // corner 0, scene units (metres for glTF)
    vec3 b;  // corner 1, scene units
    vec3 c;  // corner 2, scene units
    vec3 normal;  // unit geometric (face) normal, normalize(cross(b - a, c - a))
    float area;  // scene units squared, > 0
    float pad0;  // padding to 64 bytes (one cache line); must be ignored
    float pad1;
    float pad2;
};

// Unoccluded factors of one unordered pair as pairFactors returns them. 8 bytes.
struct PairFactors {
    float fij;  // fraction of the energy leaving i that arrives at j, dimensionless
    float fji;  // fraction leaving j arriving at i; A_i fij = A_j fji (reciprocity)
};

// One node of the flat BVH (raycast/flat_bvh.h), 32 bytes, nodes in depth-first order with the
// root at 0. Interior node (count == 0): its children are nodes `first` and `first + 1`. Leaf
// (count > 0): triangles first .. first + count - 1 of the BVH's triangle array.
struct BvhNode {
    vec3 lo;  // bounding box minimum corner, scene units
    uint first;  // interior: index of the first child; leaf: index of the first triangle
    vec3 hi;  // bounding box maximum corner, scene units
    uint count;  // leaf: number of triangles (> 0); interior: 0
};

// A triangle in BVH leaf order, 40 bytes: its corners as float world positions (counter-clockwise
// about the patch normal) and the patch it belongs to.
struct BvhTriangle {
    vec3 a;  // scene units
    vec3 b;  // scene units
    vec3 c;  // scene units
    uint patchIndex;  // index into the PatchMesh
};

// One unordered pair handed to the pair kernel, i < j. 8 bytes.
struct PairIndex {
    uint i;  // patch index
    uint j;  // patch index, > i
};

// Push constants of the pair kernel (shaders/form_factors.comp.glsl) and the arguments the CPU
// reference backend passes the same way. Device addresses are Vulkan buffer device addresses
// (GLSL: GL_EXT_shader_explicit_arithmetic_types_int64 and GL_EXT_buffer_reference). 80 bytes.
struct PairKernelParams {
    uint64_t patches;  // address of PatchGeometry[patchCount]
    uint64_t nodes;  // address of BvhNode[]
    uint64_t triangles;  // address of BvhTriangle[]
    uint64_t pairs;  // address of PairIndex[], this batch
    uint64_t results;  // address of PairFactors[], this batch, same indices as pairs
    uint pairOffset;  // first pair of this dispatch within the batch
    uint pairCount;  // pairs of this dispatch
    int method;  // DAISY_METHOD_* (the GLSL kernel takes it as a specialisation constant)
    int level;  // quadrature level L (likewise)
    int rays;  // K shadow segments per pair; 0 = no visibility (V = 1)
    uint seed;  // 32-bit seed of the per-pair sample sequence (rng.h pairSeed)
    float clearance;  // relative end clearance of shadow segments (pairClearance, visibility.h)
    uint pad0;  // padding to a multiple of 8 bytes; must be ignored
    // device address of the top-level acceleration structure over the patches' triangles (the
    // vulkan backend's ray-query variant, GL_EXT_ray_query); 0 where the BVH walk traces
    uint64_t scene;
};

// Builds a PatchGeometry from its corners (counter-clockwise about the front side).
DAISY_HD PatchGeometry makePatchGeometry(vec3 a, vec3 b, vec3 c) {
    PatchGeometry g;
    g.a = a;
    g.b = b;
    g.c = c;
    vec3 n = cross(b - a, c - a);
    float twiceArea = length(n);
    g.normal = n * (1.0f / twiceArea);
    g.area = 0.5f * twiceArea;
    g.pad0 = 0.0f;
    g.pad1 = 0.0f;
    g.pad2 = 0.0f;
    return g;
}

DAISY_HD vec3 patchCentroid(DAISY_IN(PatchGeometry) t) {
    return (t.a + t.b + t.c) * (1.0f / 3.0f);
}

// A strict, geometry-only total order on patches, used to pick one orientation of an unordered
// pair independently of argument order: the smaller area first (it gets the quadrature points,
// DESIGN.md section 3), ties broken by the corners' coordinates. Identical geometry compares
// equal both ways, and then either choice gives the same numbers.
DAISY_HD bool patchPrecedes(DAISY_IN(PatchGeometry) i, DAISY_IN(PatchGeometry) j) {
    if (i.area != j.area) return i.area < j.area;
    float ki[9] = {i.a.x, i.a.y, i.a.z, i.b.x, i.b.y, i.b.z, i.c.x, i.c.y, i.c.z};
    float kj[9] = {j.a.x, j.a.y, j.a.z, j.b.x, j.b.y, j.b.z, j.c.x, j.c.y, j.c.z};
    for (int k = 0; k < 9; ++k) {
        if (ki[k] != kj[k]) return ki[k] < kj[k];
    }
    return false;
}

DAISY_SHARED_END

#ifndef DAISY_GLSL
static_assert(sizeof(daisy::shared::PatchGeometry) == 64);
static_assert(offsetof(daisy::shared::PatchGeometry, a) == 0);
static_assert(offsetof(daisy::shared::PatchGeometry, b) == 12);
static_assert(offsetof(daisy::shared::PatchGeometry, c) == 24);
static_assert(offsetof(daisy::shared::PatchGeometry, normal) == 36);
static_assert(offsetof(daisy::shared::PatchGeometry, area) == 48);
static_assert(offsetof(daisy::shared::PatchGeometry, pad0) == 52);
static_assert(sizeof(daisy::shared::PairFactors) == 8);
static_assert(sizeof(daisy::shared::BvhNode) == 32);
static_assert(offsetof(daisy::shared::BvhNode, first) == 12);
static_assert(offsetof(daisy::shared::BvhNode, hi) == 16);
static_assert(offsetof(daisy::shared::BvhNode, count) == 28);
static_assert(sizeof(daisy::shared::BvhTriangle) == 40);
static_assert(offsetof(daisy::shared::BvhTriangle, patchIndex) == 36);
static_assert(sizeof(daisy::shared::PairIndex) == 8);
static_assert(sizeof(daisy::shared::PairKernelParams) == 80);
static_assert(offsetof(daisy::shared::PairKernelParams, pairOffset) == 40);
static_assert(offsetof(daisy::shared::PairKernelParams, clearance) == 64);
static_assert(offsetof(daisy::shared::PairKernelParams, scene) == 72);
static_assert(offsetof(daisy::shared::PairFactors, fji) == 4);
#endif

#endif  // DAISY_SHARED_GPU_TYPES_H
