#pragma once
// The ray-cast image renderer (DESIGN.md section 7): one Embree primary ray per sample, the hit
// patch and its barycentric coordinates, and barycentric interpolation of per-corner values
// (vertex_radiance.h). N x N stratified supersampling per pixel (box filter); rays that miss
// get the background value. Parallel over rows (TBB); deterministic.
#include <span>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "image/image.h"
#include "scene/scene.h"

namespace daisy {

struct RenderSettings {
    int width = 640;
    int height = 480;
    int samplesPerPixel = 1;  // N x N per pixel where N = ceil(sqrt(spp)); 1 = pixel centre
    int threads = 0;  // 0 = all hardware threads
};

// Renders `channels` values per pixel from per-corner values (cornerValues()'s layout). A pixel
// is the mean of its samples; a sample that misses takes background[c] (background.size() ==
// channels). Fails (no crash) when Embree cannot build the scene.
Expected<Image> renderCornerValues(const PatchMesh& mesh, const Camera& camera,
                                   const RenderSettings& settings, std::span<const float> corners,
                                   int channels, std::span<const float> background);

}  // namespace daisy
