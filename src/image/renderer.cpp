#include "image/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "backend/embree_ray_caster.h"
#include "core/check.h"
#include "core/strings.h"
#include "image/camera.h"

namespace daisy {

namespace {

// Well inside Embree's FLT_LARGE (1.844e18), and what scene/validate_scene.h allows for scenes.
constexpr double kMaxRayOrigin = 1e17;

// Samples per pixel side: N = ceil(sqrt(spp)), at least 1.
int samplesPerSide(int samplesPerPixel) {
    int n = 1;
    while (n * n < samplesPerPixel)
        ++n;
    return n;
}

}  // namespace

uint64_t renderImageBytes(const RenderSettings& settings, int channels) {
    return uint64_t(std::max(settings.width, 0)) * uint64_t(std::max(settings.height, 0)) *
        uint64_t(std::max(channels, 0)) * sizeof(float) * 3;
}

Expected<Image> renderCornerValues(const PatchMesh& mesh, const Camera& camera,
                                   const RenderSettings& settings, std::span<const float> corners,
                                   int channels, std::span<const float> background,
                                   const SampleShader* shader) {
    DAISY_CHECK(channels > 0);
    DAISY_CHECK(corners.size() == mesh.patchCount() * 3 * std::size_t(channels));
    DAISY_CHECK(background.size() == std::size_t(channels));
    if (settings.width <= 0 || settings.height <= 0 || settings.samplesPerPixel <= 0) {
        return Error{concat("render: image size ", settings.width, " x ", settings.height, " and ",
                            settings.samplesPerPixel, " samples per pixel must all be positive")};
    }
    if (const uint64_t bytes = renderImageBytes(settings, channels);
        settings.maxMemoryBytes != 0 && bytes > settings.maxMemoryBytes) {
        return Error{concat("render: a ", settings.width, " x ", settings.height, " image of ",
                            channels, " channels needs about ", formatBytes(double(bytes)),
                            ", over --max-memory ", formatBytes(double(settings.maxMemoryBytes)))};
    }
    // Embree asserts on rays it cannot represent (ray.valid(): |origin| under 1.8e18, finite
    // direction); scenes are range-checked on load, but a camera may come from elsewhere.
    if (!isFinite(camera.position) || !isFinite(camera.forward) || !isFinite(camera.up) ||
        std::max({std::abs(camera.position.x), std::abs(camera.position.y),
                  std::abs(camera.position.z)}) > kMaxRayOrigin) {
        return Error{concat("render: camera '", camera.name, "' at ", camera.position,
                            " is outside what float32 ray tracing represents (coordinates up to ",
                            formatNumber(kMaxRayOrigin), ")")};
    }
    // Watertight (robust) intersection: no background between patches (issue 19).
    auto caster = EmbreeRayCaster::create(mesh, PacketMode::Packet16, /*robust=*/true);
    if (!caster) return withContext(caster.error(), "render");
    const EmbreeRayCaster& tracer = **caster;

    const int side = samplesPerSide(settings.samplesPerPixel);
    const std::size_t stride = std::size_t(channels);
    const std::size_t rowSamples = std::size_t(settings.width) * side * side;
    const double sampleWeight = 1.0 / (double(side) * side);
    Image image(settings.width, settings.height, channels);

    const auto renderRows = [&](const tbb::blocked_range<int>& rows) {
        std::vector<Ray> rays(rowSamples);
        std::vector<SurfaceHit> hits(rowSamples);
        std::vector<double> sum(stride), sample(stride);
        for (int y = rows.begin(); y != rows.end(); ++y) {
            // Sample (i, j) of pixel (x, y) sits at the centre of stratum (i, j) of an N x N
            // grid over the pixel: a regular, deterministic box-filter supersampling.
            std::size_t k = 0;
            for (int x = 0; x < settings.width; ++x) {
                for (int j = 0; j < side; ++j) {
                    for (int i = 0; i < side; ++i) {
                        rays[k++] = primaryRay(camera, settings.width, settings.height,
                                               x + (i + 0.5) / side, y + (j + 0.5) / side);
                    }
                }
            }
            tracer.closestSurfaceHits(rays, hits);
            k = 0;
            for (int x = 0; x < settings.width; ++x) {
                std::fill(sum.begin(), sum.end(), 0.0);
                for (int s = 0; s < side * side; ++s, ++k) {
                    SurfaceHit& hit = hits[k];
                    if (shader != nullptr && hit.patch != kNoPatch) shader->resolve(rays[k], hit);
                    if (hit.patch == kNoPatch) {
                        for (std::size_t c = 0; c < stride; ++c)
                            sum[c] += background[c];
                        continue;
                    }
                    // Embree's barycentrics weight corners 1 and 2; corner 0 takes the rest.
                    const double w1 = hit.u;
                    const double w2 = hit.v;
                    const double w0 = 1 - w1 - w2;
                    const float* v = corners.data() + std::size_t(hit.patch) * 3 * stride;
                    for (std::size_t c = 0; c < stride; ++c)
                        sample[c] = w0 * v[c] + w1 * v[stride + c] + w2 * v[2 * stride + c];
                    if (shader != nullptr) shader->shade(hit, sample);
                    for (std::size_t c = 0; c < stride; ++c)
                        sum[c] += sample[c];
                }
                float* out = image.at(x, y);
                for (std::size_t c = 0; c < stride; ++c)
                    out[c] = static_cast<float>(sum[c] * sampleWeight);
            }
        }
    };
    const tbb::blocked_range<int> allRows(0, settings.height, 1);
    if (settings.threads > 0) {
        tbb::task_arena arena(settings.threads);
        arena.execute([&] { tbb::parallel_for(allRows, renderRows); });
    } else {
        tbb::parallel_for(allRows, renderRows);
    }
    return image;
}

}  // namespace daisy
