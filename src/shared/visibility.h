// Visibility V_ij between two patches (DESIGN.md section 3): the kernel-weighted unblocked share
// of the pair's K shadow segments, traced any-hit through the flat BVH. The segments are exactly
// those of the cpu backend (radiosity/visibility_samples.h shadowSegments): the same sample
// points, trimming and weights, so backends differ only where their ray tests do.
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
// make every segment empty. The cpu backend's segments use the same function.
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
// with them) never block it. `weight` is the form-factor kernel at the untrimmed end points,
// cos_i cos_j / r^2 = (n_i . d / r^2) (-n_j . d / r^2) with d = p_j - p_i, and 0 where either
// point is behind the other's plane (the part of a straddling patch the unoccluded factor leaves
// out) or the points coincide. Returns false when nothing is left (too grazing): such a segment is
// never blocked. Same arithmetic as shadowSegments, operation for operation.
DAISY_HD bool shadowSegment(uint pairSeedValue, int k, int rays, DAISY_IN(PatchGeometry) i,
                            DAISY_IN(PatchGeometry) j, float clearance, DAISY_INOUT(vec3) origin,
                            DAISY_INOUT(vec3) end, DAISY_INOUT(float) weight) {
    vec3 pi;
    vec3 pj;
    visibilitySamplePair(pairSeedValue, k, rays, i, j, pi, pj);
    vec3 d = pj - pi;
    float cosI = i.normal.x * d.x + i.normal.y * d.y + i.normal.z * d.z;
    float cosJ = -(j.normal.x * d.x + j.normal.y * d.y + j.normal.z * d.z);
    float leave = abs(cosI);
    float arrive = abs(cosJ);
    float r2 = d.x * d.x + d.y * d.y + d.z * d.z;
    weight = r2 > 0.0f && cosI > 0.0f && cosJ > 0.0f ? (cosI / r2) * (cosJ / r2) : 0.0f;
    // shadowSegments divides by zero (inf, then empty); GLSL leaves x / 0 undefined, so test.
    if (!(leave > 0.0f && arrive > 0.0f)) return false;
    float t0 = clearance / leave;
    float t1 = 1.0f - clearance / arrive;
    if (!(t0 < t1)) return false;
    origin = pi + d * t0;
    end = pi + d * t1;
    return !(origin.x == end.x && origin.y == end.y && origin.z == end.z);
}

// V_ij from a pair's segments: the kernel-weighted open share sum_open w / sum w
// (`seen` and `total`, summed in segment order), not the plain open fraction. V_ij is the
// kernel-weighted mean of point-to-point visibility (F_ij = Fu_ij V_ij exactly when V is
// weighted by cos_i cos_j / r^2), so the plain fraction is biased wherever the hidden part of a
// pair is nearer or farther than the rest, and rows of F then stop summing to 1 however many
// rays a pair takes. Exactly 1 (0) when every segment is open (blocked); the plain fraction
// when the weights are not usable (all 0, or overflowed).
DAISY_HD float kernelWeightedVisibility(float seen, float total, int open, int rays) {
    if (open == rays) return 1.0f;
    if (open == 0) return 0.0f;
    if (total > 0.0f && total < 3.0e38f) return min(1.0f, seen / total);
    return float(open) / float(rays);
}

// V_ij in [0, 1]: kernelWeightedVisibility of the pair's `rays` (K >= 1) shadow segments, a
// segment open when no triangle blocks it for t in (DAISY_SEGMENT_MARGIN, 1 - DAISY_SEGMENT_MARGIN)
// (the cpu backend's span). pairSeedValue = pairSeed(i, j, seed) (rng.h). The cpu backend passes
// pairs as i < j; swapping i and j traces the same segments reversed (equal up to rounding).
// The any-hit test is the flat BVH walk (bvhOccluded over nodes and triangles) unless the
// including shader defines DAISY_SEGMENT_OCCLUDED(org, dir, tmin, tmax) first: the ray-query
// variant of shaders/form_factors.comp.glsl traces the device's acceleration structure over
// the same triangles instead (nodes and triangles are then unused), with the same segments,
// span and weights.
DAISY_HD float pairVisibility(uint pairSeedValue, int rays, DAISY_IN(PatchGeometry) i,
                              DAISY_IN(PatchGeometry) j, float clearance, BvhNodeBuffer nodes,
                              BvhTriangleBuffer triangles) {
    int open = 0;
    float seen = 0.0f;
    float total = 0.0f;
    for (int k = 0; k < rays; ++k) {
        vec3 origin = vec3(0.0f);
        vec3 end = vec3(0.0f);
        float weight = 0.0f;
        bool blocked = false;
        if (shadowSegment(pairSeedValue, k, rays, i, j, clearance, origin, end, weight)) {
#ifdef DAISY_SEGMENT_OCCLUDED
            blocked = DAISY_SEGMENT_OCCLUDED(origin, end - origin, DAISY_SEGMENT_MARGIN,
                                             1.0f - DAISY_SEGMENT_MARGIN);
#else
            blocked = bvhOccluded(origin, end - origin, DAISY_SEGMENT_MARGIN,
                                  1.0f - DAISY_SEGMENT_MARGIN, nodes, triangles);
#endif
        }
        total += weight;
        if (!blocked) {
            seen += weight;
            open += 1;
        }
    }
    return kernelWeightedVisibility(seen, total, open, rays);
}

DAISY_SHARED_END

#endif  // DAISY_SHARED_VISIBILITY_H
