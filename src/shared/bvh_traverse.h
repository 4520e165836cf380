// Traversal of the flat BVH (gpu_types.h BvhNode / BvhTriangle, built by raycast/flat_bvh.h):
// an explicit stack (no recursion in the dialect) of DAISY_BVH_STACK_SIZE entries, enough for
// any tree the builder makes. Rays are org + t dir, t in units of |dir|; both triangle sides hit.
// Preconditions: the BVH has at least one triangle and dir != 0.
#ifndef DAISY_SHARED_BVH_TRAVERSE_H
#define DAISY_SHARED_BVH_TRAVERSE_H

#include "config.h"
#include "gpu_types.h"
#include "intersect.h"
#include "prelude.h"

DAISY_SHARED_BEGIN

DAISY_BUFFER(BvhNodeBuffer, BvhNode);
DAISY_BUFFER(BvhTriangleBuffer, BvhTriangle);

// The closest hit of a ray: triangle index in BVH leaf order (or DAISY_NO_HIT), its patch and t.
#define DAISY_NO_HIT 0xffffffffu
struct BvhHit {
    float t;  // units of |dir|
    uint triangle;  // index into the BVH's triangle array, DAISY_NO_HIT when nothing was hit
    uint patchIndex;  // that triangle's patch, DAISY_NO_HIT when nothing was hit
};

// True when some triangle crosses the ray at tmin < t < tmax (any hit: stops at the first).
DAISY_HD bool bvhOccluded(vec3 org, vec3 dir, float tmin, float tmax, BvhNodeBuffer nodes,
                          BvhTriangleBuffer triangles) {
    WatertightRay ray = makeWatertightRay(org, dir);
    vec3 invDir = safeReciprocal(dir);
    uint stack[DAISY_BVH_STACK_SIZE];
    int top = 0;
    uint node = 0u;
    float entry = 0.0f;
    if (!intersectBox(org, invDir, nodes.v[0].lo, nodes.v[0].hi, tmin, tmax, entry)) return false;
    while (true) {
        BvhNode n = nodes.v[node];
        if (n.count > 0u) {
            for (uint k = n.first; k < n.first + n.count; ++k) {
                BvhTriangle tri = triangles.v[k];
                float t = 0.0f;
                if (intersectTriangle(ray, tri.a, tri.b, tri.c, tmin, tmax, t)) return true;
            }
        } else {
            BvhNode left = nodes.v[n.first];
            BvhNode right = nodes.v[n.first + 1u];
            float leftEntry = 0.0f;
            float rightEntry = 0.0f;
            bool hitLeft = intersectBox(org, invDir, left.lo, left.hi, tmin, tmax, leftEntry);
            bool hitRight = intersectBox(org, invDir, right.lo, right.hi, tmin, tmax, rightEntry);
            if (hitLeft && hitRight) {
                // The nearer child first: a blocker near the origin ends the search sooner.
                bool leftFirst = leftEntry <= rightEntry;
                if (top < DAISY_BVH_STACK_SIZE) {
                    stack[top] = leftFirst ? n.first + 1u : n.first;
                    top += 1;
                }
                node = leftFirst ? n.first : n.first + 1u;
                continue;
            }
            if (hitLeft || hitRight) {
                node = hitLeft ? n.first : n.first + 1u;
                continue;
            }
        }
        if (top == 0) break;
        top -= 1;
        node = stack[top];
    }
    return false;
}

// The nearest triangle crossing the ray at tmin < t < tmax; hit.triangle = DAISY_NO_HIT if none.
DAISY_HD BvhHit bvhClosestHit(vec3 org, vec3 dir, float tmin, float tmax, BvhNodeBuffer nodes,
                              BvhTriangleBuffer triangles) {
    BvhHit hit;
    hit.t = tmax;
    hit.triangle = DAISY_NO_HIT;
    hit.patchIndex = DAISY_NO_HIT;
    WatertightRay ray = makeWatertightRay(org, dir);
    vec3 invDir = safeReciprocal(dir);
    uint stack[DAISY_BVH_STACK_SIZE];
    float stackEntry[DAISY_BVH_STACK_SIZE];
    int top = 0;
    uint node = 0u;
    float entry = 0.0f;
    if (!intersectBox(org, invDir, nodes.v[0].lo, nodes.v[0].hi, tmin, tmax, entry)) return hit;
    while (true) {
        BvhNode n = nodes.v[node];
        if (n.count > 0u) {
            for (uint k = n.first; k < n.first + n.count; ++k) {
                BvhTriangle tri = triangles.v[k];
                float t = 0.0f;
                if (intersectTriangle(ray, tri.a, tri.b, tri.c, tmin, hit.t, t)) {
                    hit.t = t;
                    hit.triangle = k;
                    hit.patchIndex = tri.patchIndex;
                }
            }
        } else {
            BvhNode left = nodes.v[n.first];
            BvhNode right = nodes.v[n.first + 1u];
            float leftEntry = 0.0f;
            float rightEntry = 0.0f;
            bool hitLeft = intersectBox(org, invDir, left.lo, left.hi, tmin, hit.t, leftEntry);
            bool hitRight = intersectBox(org, invDir, right.lo, right.hi, tmin, hit.t, rightEntry);
            if (hitLeft && hitRight) {
                bool leftFirst = leftEntry <= rightEntry;
                if (top < DAISY_BVH_STACK_SIZE) {
                    stack[top] = leftFirst ? n.first + 1u : n.first;
                    stackEntry[top] = leftFirst ? rightEntry : leftEntry;
                    top += 1;
                }
                node = leftFirst ? n.first : n.first + 1u;
                continue;
            }
            if (hitLeft || hitRight) {
                node = hitLeft ? n.first : n.first + 1u;
                continue;
            }
        }
        // Pop, skipping nodes entered beyond the closest hit found since they were pushed.
        bool found = false;
        while (top > 0 && !found) {
            top -= 1;
            node = stack[top];
            found = stackEntry[top] <= hit.t * 1.00000036f;
        }
        if (!found) break;
    }
    return hit;
}

DAISY_SHARED_END

#endif  // DAISY_SHARED_BVH_TRAVERSE_H
