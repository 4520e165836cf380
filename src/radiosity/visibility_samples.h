#pragma once
// All K shadow-segment end points of one pair at once: bit-identical to K calls of
// shared::visibilitySamplePair(pairSeed, k, K, i, j, pi, pj) (shared/sampling.h, the sequence
// every backend uses), with what depends only on the pair (stream seeds, digit scrambles, jitter
// seeds, the pair's orientation) computed once instead of K times, which makes generation about
// several times faster. tests/radiosity/visibility_samples_test.cpp holds the two equal.

#include "raycast/ray.h"
#include "shared/gpu_types.h"

namespace daisy {

// pi[k], pj[k] for k < count: points on i and j (count >= 1).
void visibilitySamples(uint32_t pairSeedValue, int count, const shared::PatchGeometry& i,
                       const shared::PatchGeometry& j, shared::vec3* pi, shared::vec3* pj);

// The pair's `count` shadow segments from pi[k] to pj[k], each trimmed at both ends to where it
// is `clearance` (scene units) away from that end's patch plane: the two patches never block
// their own segments, however grazing (their own shading is the kernel's cosines), nor do
// patches coplanar with them. A segment too grazing to keep anything comes back empty
// (origin == end), which ray casters never report as blocked.
// Written to out at [offset, offset + count); weights[0, count) gets each segment's kernel
// weight (shared::shadowSegment's `weight`, for shared::kernelWeightedVisibility).
void shadowSegments(uint32_t pairSeedValue, int count, const shared::PatchGeometry& i,
                    const shared::PatchGeometry& j, float clearance, SegmentArrays& out,
                    std::size_t offset, float* weights);

}  // namespace daisy
