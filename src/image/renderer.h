#pragma once
// The ray-cast image renderer (DESIGN.md section 7): one primary ray per sample, the hit
// patch and its barycentric coordinates, and barycentric interpolation of per-corner values
// (vertex_radiance.h). N x N stratified supersampling per pixel (box filter); rays that miss
// get the background value. Parallel over rows (TBB); deterministic.
#include <cstdint>
#include <span>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "image/image.h"
#include "raycast/ray.h"
#include "scene/scene.h"

namespace daisy {

struct RenderSettings {
    int width = 640;
    int height = 480;
    int samplesPerPixel = 1;  // N x N per pixel where N = ceil(sqrt(spp)); 1 = pixel centre
    int threads = 0;  // 0 = all hardware threads
    uint64_t maxMemoryBytes = 0;  // --max-memory: refuse images needing more; 0 = no limit
    // Edge-adaptive supersampling (image/edge_sampling.h): pixels on a silhouette, crease or
    // material boundary take this many samples (N x N), the others samplesPerPixel; 0 = off.
    // renderRadiosityImage turns it into pixelSides.
    int edgeSamplesPerPixel = 0;
    // Per pixel (row-major) the side N of its N x N sample grid, borrowed for the call; empty =
    // samplesPerSide(samplesPerPixel) everywhere. renderCornerValues and renderDirectLight
    // follow it, so their samples coincide.
    std::span<const uint8_t> pixelSides;
};

// Side of pixel (x, y)'s sample grid under `settings` (pixelSides or the uniform side).
int pixelSide(const RenderSettings& settings, int x, int y);

// Bytes of the rendered image and the copies a front end makes of it (exposure, RGB): about
// three float images of `channels` channels.
uint64_t renderImageBytes(const RenderSettings& settings, int channels);

// Per-sample adjustments (image/texture_detail.h): `resolve` may replace a hit (the back patch
// of a double-sided surface seen from behind), `shade` scales a hit's interpolated channel
// values in place (texture detail). Both are called from many threads at once.
class SampleShader {
public:
    virtual ~SampleShader() = default;
    virtual void resolve(const Ray& ray, SurfaceHit& hit) const = 0;
    virtual void shade(const SurfaceHit& hit, std::span<double> values) const = 0;
};

// Renders `channels` values per pixel from per-corner values (cornerValues()'s layout). A pixel
// is the mean of its samples; a sample that misses takes background[c] (background.size() ==
// channels), and one on the back of a one-sided patch (after the shader's resolve) backFace[c]
// when backFace is given (a back face neither emits nor reflects: black, but covered), else the
// patch's own values. Fails (no crash) when the ray caster cannot build the scene, when the
// camera lies outside what float32 rays represent, and when renderImageBytes exceeds
// settings.maxMemoryBytes.
Expected<Image> renderCornerValues(const PatchMesh& mesh, const Camera& camera,
                                   const RenderSettings& settings, std::span<const float> corners,
                                   int channels, std::span<const float> background,
                                   const SampleShader* shader = nullptr,
                                   std::span<const float> backFace = {});

// Per patch, 1 when a sample of the image (renderCornerValues' rays and hits, after the
// shader's resolve) lands on it or on a patch sharing a vertex with it (whose corner values
// cornerValues() may average into it), else 0: what an image needs of the patches. Fails as
// renderCornerValues on the ray caster and the camera.
Expected<std::vector<uint8_t>> patchesInView(const PatchMesh& mesh, const Camera& camera,
                                             const RenderSettings& settings,
                                             const SampleShader* shader = nullptr);

}  // namespace daisy
