#pragma once
// The plain data of ray queries, shared by every caller of a RayCaster (raycast/ray_caster.h):
// rays, shadow segments in structure-of-arrays form, and closest hits with their position on
// the hit patch. Scene units throughout; patches are indices into the PatchMesh the caster was
// built from.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace daisy {

// Shadow segments as six arrays (structure of arrays, as ray packets take them): segment k runs
// from (x0[k], y0[k], z0[k]) to (x1[k], y1[k], z1[k]), scene units, float.
struct SegmentArrays {
    std::vector<float> x0, y0, z0, x1, y1, z1;

    std::size_t size() const { return x0.size(); }
    void resize(std::size_t n) {
        for (std::vector<float>* v : {&x0, &y0, &z0, &x1, &y1, &z1})
            v->resize(n);
    }
    void set(std::size_t k, float ox, float oy, float oz, float ex, float ey, float ez) {
        x0[k] = ox, y0[k] = oy, z0[k] = oz, x1[k] = ex, y1[k] = ey, z1[k] = ez;
    }
    bool empty(std::size_t k) const { return x0[k] == x1[k] && y0[k] == y1[k] && z0[k] == z1[k]; }
};

// A ray for closest-hit queries: origin (scene units) and unit direction.
struct Ray {
    float origin[3];
    float direction[3];
};

// The patch index of a miss.
inline constexpr uint32_t kNoPatch = 0xffffffffu;

// A closest hit with its position on the patch: the hit point is
// (1 - u - v) * corner0 + u * corner1 + v * corner2 with the patch's corners in PatchMesh order
// (the barycentrics of the triangle as the caster built it), at distance t along the ray (scene
// units for a unit direction). patch = kNoPatch (u = v = 0, t = infinity) for a miss.
struct SurfaceHit {
    uint32_t patch;
    float u, v, t;
};

}  // namespace daisy
