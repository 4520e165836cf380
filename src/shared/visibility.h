// Visibility V_ij between two patches (DESIGN.md section 3): the unblocked fraction of the pair's
// K shadow segments, traced any-hit through the flat BVH. The segments are exactly those of the
// cpu backend (radiosity/visibility_samples.h shadowSegments): the same sample points and the
// same trimming, so backends differ only where their ray tests do.
#ifndef DAISY_SHARED_VISIBILITY_H
#define DAISY_SHARED_VISIBILITY_H

#include "bvh_traverse.h"
#include "config.h"
#include "gpu_types.h"
#include "prelude.h"
#include "sampling.h"

DAISY_SHARED_BEGIN

// A pair's end clearance (scene units): `relative` times the largest coordinate magnitude among
// the two patches' corners, i.e. a fixed number of float roundings of where these two patches
// are. Relative to the patches involved, never to the scene's size, so one far triangle cannot
// make every segment empty (issue 18). The cpu backend's segments use the same function.
DAISY_HD float pairClearance(float relative, DAISY_IN(PatchGeometry) i, DAISY_IN(PatchGeometry) j) {
    vec3 c[6] = {i.a, i.b, i.c, j.a, j.b, j.c};
    float m = 0.0f;
    for (int k = 0; k < 6; ++k) {
        m = max(m, max(max(abs(c[k].x), abs(c[k].y)), abs(c[k].z)));
    }
    return relative * m;
}

// Shadow segment k of `rays` of the pair (pairSeedValue = pairSeed(i, j, seed)): from the sample
// point on i towards the one on j (visibilitySamplePair), trimmed at both ends to where it is
// `clearance` (scene units) from that end's patch plane, so the two patches (and patches coplanar
// with them) never block it. Returns false when nothing is left (too grazing): such a segment is
// never blocked. Same arithmetic as shadowSegments, operation for operation.
DAISY_HD bool shadowSegment(uint pairSeedValue, int k, int rays, DAISY_IN(PatchGeometry) i,
                            DAISY_IN(PatchGeometry) j, float clearance, DAISY_INOUT(vec3) origin,
                            DAISY_INOUT(vec3) end) {
    vec3 pi;
    vec3 pj;
    visibilitySamplePair(pairSeedValue, k, rays, i, j, pi, pj);
    vec3 d = pj - pi;
    float leave = abs(i.normal.x * d.x + i.normal.y * d.y + i.normal.z * d.z);
    float arrive = abs(j.normal.x * d.x + j.normal.y * d.y + j.normal.z * d.z);
    // shadowSegments divides by zero (inf, then empty); GLSL leaves x / 0 undefined, so test.
    if (!(leave > 0.0f && arrive > 0.0f)) return false;
    float t0 = clearance / leave;
    float t1 = 1.0f - clearance / arrive;
    if (!(t0 < t1)) return false;
    origin = pi + d * t0;
    end = pi + d * t1;
    return !(origin.x == end.x && origin.y == end.y && origin.z == end.z);
}

// V_ij in [0, 1]: the fraction of the pair's `rays` (K >= 1) shadow segments no triangle blocks
// for t in (DAISY_SEGMENT_MARGIN, 1 - DAISY_SEGMENT_MARGIN) of the segment (the cpu backend's
// span). pairSeedValue = pairSeed(i, j, seed) (rng.h). The cpu backend passes pairs as i < j;
// swapping i and j traces the same segments reversed (equal up to rounding).
DAISY_HD float pairVisibility(uint pairSeedValue, int rays, DAISY_IN(PatchGeometry) i,
                              DAISY_IN(PatchGeometry) j, float clearance, BvhNodeBuffer nodes,
                              BvhTriangleBuffer triangles) {
    int open = 0;
    for (int k = 0; k < rays; ++k) {
        vec3 origin = vec3(0.0f);
        vec3 end = vec3(0.0f);
        bool blocked = false;
        if (shadowSegment(pairSeedValue, k, rays, i, j, clearance, origin, end)) {
            blocked = bvhOccluded(origin, end - origin, DAISY_SEGMENT_MARGIN,
                                  1.0f - DAISY_SEGMENT_MARGIN, nodes, triangles);
        }
        open += blocked ? 0 : 1;
    }
    return float(open) / float(rays);
}

DAISY_SHARED_END

#endif  // DAISY_SHARED_VISIBILITY_H
