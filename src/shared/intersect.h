// Ray-primitive tests of the BVH traversal (bvh_traverse.h): a watertight ray-triangle test and
// a robust slab ray-box test. Rays are org + t dir with dir not necessarily unit; t is in units of
// |dir|. Both sides of a triangle are hit (shadow rays and the stochastic rays need both).
#ifndef DAISY_SHARED_INTERSECT_H
#define DAISY_SHARED_INTERSECT_H

#include "config.h"
#include "prelude.h"

DAISY_SHARED_BEGIN

// Component k (0, 1, 2) of v: GLSL indexes vectors, the C++ vec3 has no operator[].
DAISY_HD float vecComponent(vec3 v, int k) {
    return k == 0 ? v.x : (k == 1 ? v.y : v.z);
}

// The per-ray constants of the watertight test (Woop, Benthin & Wald 2013, "Watertight
// Ray/Triangle Intersection", JCGT 2(1), section 3): the axis kz where |dir| is largest, kx and
// ky after it (swapped when dir[kz] < 0 to keep the winding), and the shear that maps dir to
// the unit kz axis.
struct WatertightRay {
    vec3 org;  // scene units
    int kx;
    int ky;
    int kz;
    float sx;  // shear constants: dir[kx] / dir[kz], dir[ky] / dir[kz], 1 / dir[kz]
    float sy;
    float sz;
};

// Precondition: dir != 0.
DAISY_HD WatertightRay makeWatertightRay(vec3 org, vec3 dir) {
    WatertightRay r;
    r.org = org;
    float ax = abs(dir.x);
    float ay = abs(dir.y);
    float az = abs(dir.z);
    r.kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
    r.kx = r.kz == 2 ? 0 : r.kz + 1;
    r.ky = r.kx == 2 ? 0 : r.kx + 1;
    float dz = vecComponent(dir, r.kz);
    if (dz < 0.0f) {
        int swapped = r.kx;
        r.kx = r.ky;
        r.ky = swapped;
    }
    r.sx = vecComponent(dir, r.kx) / dz;
    r.sy = vecComponent(dir, r.ky) / dz;
    r.sz = 1.0f / dz;
    return r;
}

// Edge function e of the directed edge p -> q (sheared 2D coordinates relative to the ray),
// e = q.x p.y - q.y p.x, with an exact zero resolved by symbolic perturbation of the ray
// (Edelsbrunner & Muecke 1990, "Simulation of Simplicity", ACM TOG 9(1)): the ray moved by
// (eps, eps^2) gives e + eps dy - eps^2 dx, d = q - p. Reversing the edge negates the result
// exactly, so a ray through an edge or vertex shared by triangles counts in exactly one of them
// (the same rule as rasterisers' top-left fill convention). Returns 0 only for a point edge.
DAISY_HD float perturbedEdge(float e, float px, float py, float qx, float qy) {
    if (e != 0.0f) return e;
    float dy = qy - py;
    if (dy != 0.0f) return dy;
    return px - qx;
}

// True when the ray hits triangle (a, b, c) at tmin < t < tmax; sets t then. Watertight (Woop et
// al. 2013): the edge functions of an edge are computed from the same sheared vertices in every
// triangle sharing it, so no ray slips between adjacent triangles. Where the paper recomputes
// exact zeros in double (not available in every GLSL device), perturbedEdge breaks the tie, so
// rays through a shared edge or vertex hit exactly one of the triangles. Degenerate triangles
// and rays in the triangle's plane miss.
DAISY_HD bool intersectTriangle(DAISY_IN(WatertightRay) r, vec3 a, vec3 b, vec3 c, float tmin,
                                float tmax, DAISY_INOUT(float) t) {
    vec3 pa = a - r.org;
    vec3 pb = b - r.org;
    vec3 pc = c - r.org;
    float az = vecComponent(pa, r.kz);
    float bz = vecComponent(pb, r.kz);
    float cz = vecComponent(pc, r.kz);
    float ax = vecComponent(pa, r.kx) - r.sx * az;
    float ay = vecComponent(pa, r.ky) - r.sy * az;
    float bx = vecComponent(pb, r.kx) - r.sx * bz;
    float by = vecComponent(pb, r.ky) - r.sy * bz;
    float cx = vecComponent(pc, r.kx) - r.sx * cz;
    float cy = vecComponent(pc, r.ky) - r.sy * cz;
    float u = cx * by - cy * bx;  // edge b -> c
    float v = ax * cy - ay * cx;  // edge c -> a
    float w = bx * ay - by * ax;  // edge a -> b
    float det = u + v + w;
    if (det == 0.0f) return false;
    float su = perturbedEdge(u, bx, by, cx, cy);
    float sv = perturbedEdge(v, cx, cy, ax, ay);
    float sw = perturbedEdge(w, ax, ay, bx, by);
    bool inside = (su > 0.0f && sv > 0.0f && sw > 0.0f) || (su < 0.0f && sv < 0.0f && sw < 0.0f);
    if (!inside) return false;
    float hit = (u * (r.sz * az) + v * (r.sz * bz) + w * (r.sz * cz)) / det;
    if (!(hit > tmin && hit < tmax)) return false;
    t = hit;
    return true;
}

// The per-ray constants of the slab test: reciprocal direction, zero components replaced by a
// tiny value of the same sign so no 0 * inf = NaN arises for origins on a slab plane.
DAISY_HD vec3 safeReciprocal(vec3 dir) {
    float tiny = 1.0e-30f;
    float x = abs(dir.x) > tiny ? dir.x : (dir.x < 0.0f ? -tiny : tiny);
    float y = abs(dir.y) > tiny ? dir.y : (dir.y < 0.0f ? -tiny : tiny);
    float z = abs(dir.z) > tiny ? dir.z : (dir.z < 0.0f ? -tiny : tiny);
    return vec3(1.0f / x, 1.0f / y, 1.0f / z);
}

// Slab test (Kay & Kajiya 1986, "Ray Tracing Complex Scenes", SIGGRAPH) of the box [lo, hi]
// against the ray's interval [tmin, tmax]; true when they overlap, with tEntry the entry
// distance. The exit distance is scaled by 1 + 2 gamma(3) (Ize 2013, "Robust BVH Ray
// Traversal", JCGT 2(2)), so rounding never culls a box a watertight triangle test would hit.
DAISY_HD bool intersectBox(vec3 org, vec3 invDir, vec3 lo, vec3 hi, float tmin, float tmax,
                           DAISY_INOUT(float) tEntry) {
    float tx0 = (lo.x - org.x) * invDir.x;
    float tx1 = (hi.x - org.x) * invDir.x;
    float ty0 = (lo.y - org.y) * invDir.y;
    float ty1 = (hi.y - org.y) * invDir.y;
    float tz0 = (lo.z - org.z) * invDir.z;
    float tz1 = (hi.z - org.z) * invDir.z;
    float t0 = max(max(min(tx0, tx1), min(ty0, ty1)), max(min(tz0, tz1), tmin));
    float t1 = min(min(max(tx0, tx1), max(ty0, ty1)), min(max(tz0, tz1), tmax));
    tEntry = t0;
    return t0 <= t1 * 1.00000036f;
}

DAISY_SHARED_END

#endif  // DAISY_SHARED_INTERSECT_H
