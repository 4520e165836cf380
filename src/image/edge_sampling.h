#pragma once
// Edge-adaptive supersampling: the radiosity image is smooth inside a surface and
// aliased only where the surface under the pixel changes (a silhouette, a crease, a material
// boundary), so only those pixels need the many samples a box-filtered reference averages.
// One primary ray per pixel centre finds the surface; a pixel whose 3 x 3 neighbourhood of
// centre hits is not all one surface takes the edge sample count, every other pixel the base
// count. Deterministic (no randomness): the same pixels on every run.
#include <cstdint>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "image/renderer.h"

namespace daisy {

// Two centre hits lie on different surfaces when one misses and the other does not, when their
// materials differ, when their normals differ by more than 30 degrees (vertex_radiance.h's
// crease angle), or when one point lies off the other's plane by more than 1% of its distance
// from the camera (a face in front of a parallel wall).
inline constexpr double kEdgeCreaseCosine = 0.8660254037844386;  // cos 30 degrees
inline constexpr double kEdgeDepthFraction = 0.01;

// Per pixel (row-major, width x height) the side N of its N x N grid of samples:
// samplesPerSide(settings.samplesPerPixel) inside surfaces, samplesPerSide(edgeSamplesPerPixel)
// (at least the base) at edges. `shader` resolves hits as the renderer does (back patches).
// Fails (no crash) on what renderCornerValues refuses, and when a side would exceed 255.
Expected<std::vector<uint8_t>> edgeAdaptiveSides(const PatchMesh& mesh, const Camera& camera,
                                                 const RenderSettings& settings,
                                                 int edgeSamplesPerPixel,
                                                 const SampleShader* shader = nullptr);

}  // namespace daisy
