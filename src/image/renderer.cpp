#include "image/renderer.h"

#include <tbb/blocked_range.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>

#include "core/check.h"
#include "core/strings.h"
#include "image/camera.h"
#include "image/pixel_samples.h"
#include "raycast/ray_caster.h"

namespace daisy {

uint64_t renderImageBytes(const RenderSettings& settings, int channels) {
    return uint64_t(std::max(settings.width, 0)) * uint64_t(std::max(settings.height, 0)) *
        uint64_t(std::max(channels, 0)) * sizeof(float) * 3;
}

int pixelSide(const RenderSettings& settings, int x, int y) {
    if (settings.pixelSides.empty()) return samplesPerSide(settings.samplesPerPixel);
    return settings.pixelSides[std::size_t(y) * std::size_t(settings.width) + std::size_t(x)];
}

namespace {

// The most samples a row of the image takes.
std::size_t rowSampleCapacity(const RenderSettings& settings) {
    int maxSide = samplesPerSide(settings.samplesPerPixel);
    for (const uint8_t side : settings.pixelSides)
        maxSide = std::max(maxSide, int(side));
    return std::size_t(settings.width) * maxSide * maxSide;
}

// The primary rays of row y's samples, pixel by pixel, into rays (rowSampleCapacity long);
// returns their count. Sample (i, j) of pixel (x, y) sits in stratum (i, j) of its N x N grid,
// at its multi-jittered place (pixel_samples.h): deterministic box-filter supersampling.
std::size_t rowRays(const Camera& camera, const RenderSettings& settings, int y,
                    std::vector<Ray>& rays) {
    std::size_t k = 0;
    for (int x = 0; x < settings.width; ++x) {
        const int side = pixelSide(settings, x, y);
        for (int s = 0; s < side * side; ++s) {
            const auto [ox, oy] = sampleOffset(s, side);
            rays[k++] = primaryRay(camera, settings.width, settings.height, x + ox, y + oy);
        }
    }
    return k;
}

}  // namespace

Expected<Image> renderCornerValues(const PatchMesh& mesh, const Camera& camera,
                                   const RenderSettings& settings, std::span<const float> corners,
                                   int channels, std::span<const float> background,
                                   const SampleShader* shader, std::span<const float> backFace) {
    DAISY_CHECK(channels > 0);
    DAISY_CHECK(corners.size() == mesh.patchCount() * 3 * std::size_t(channels));
    DAISY_CHECK(background.size() == std::size_t(channels));
    DAISY_CHECK(backFace.empty() || backFace.size() == std::size_t(channels));
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
    if (!settings.pixelSides.empty() &&
        settings.pixelSides.size() != std::size_t(settings.width) * settings.height) {
        return Error{concat("render: ", settings.pixelSides.size(), " per-pixel sample counts for ",
                            settings.width, " x ", settings.height, " pixels")};
    }
    if (auto ok = checkRayCamera(camera); !ok) return withContext(ok.error(), "render");
    // Watertight (robust) intersection: no background between patches.
    auto caster = makeRayCaster(mesh, {.packetMode = PacketMode::Packet16, .robust = true});
    if (!caster) return withContext(caster.error(), "render");
    const RayCaster& tracer = **caster;

    const std::size_t stride = std::size_t(channels);
    const std::size_t rowSamples = rowSampleCapacity(settings);
    Image image(settings.width, settings.height, channels);

    const auto renderRows = [&](const tbb::blocked_range<int>& rows) {
        std::vector<Ray> rays(rowSamples);
        std::vector<SurfaceHit> hits(rowSamples);
        std::vector<double> sum(stride), sample(stride);
        for (int y = rows.begin(); y != rows.end(); ++y) {
            std::size_t k = rowRays(camera, settings, y, rays);
            tracer.closestSurfaceHits(std::span<const Ray>(rays.data(), k),
                                      std::span<SurfaceHit>(hits.data(), k));
            k = 0;
            for (int x = 0; x < settings.width; ++x) {
                const int side = pixelSide(settings, x, y);
                std::fill(sum.begin(), sum.end(), 0.0);
                for (int s = 0; s < side * side; ++s, ++k) {
                    SurfaceHit& hit = hits[k];
                    if (shader != nullptr && hit.patch != kNoPatch) shader->resolve(rays[k], hit);
                    if (hit.patch == kNoPatch) {
                        for (std::size_t c = 0; c < stride; ++c)
                            sum[c] += background[c];
                        continue;
                    }
                    if (!backFace.empty()) {
                        const Vec3d& n = mesh.normals[hit.patch];
                        if (n.x * rays[k].direction[0] + n.y * rays[k].direction[1] +
                                n.z * rays[k].direction[2] >=
                            0) {
                            for (std::size_t c = 0; c < stride; ++c)
                                sum[c] += backFace[c];
                            continue;
                        }
                    }
                    // The hit's barycentrics weight corners 1 and 2; corner 0 takes the rest.
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
                    out[c] = static_cast<float>(sum[c] / (side * side));
            }
        }
    };
    forEachImageRow(settings.height, settings.threads, renderRows);
    return image;
}

Expected<std::vector<uint8_t>> patchesInView(const PatchMesh& mesh, const Camera& camera,
                                             const RenderSettings& settings,
                                             const SampleShader* shader) {
    if (auto ok = checkRayCamera(camera); !ok) return withContext(ok.error(), "render");
    auto caster = makeRayCaster(mesh, {.packetMode = PacketMode::Packet16, .robust = true});
    if (!caster) return withContext(caster.error(), "render");
    const RayCaster& tracer = **caster;
    const std::size_t rowSamples = rowSampleCapacity(settings);
    // Written by many rows at once: every write is a 1.
    std::vector<std::atomic<uint8_t>> hit(mesh.patchCount());
    forEachImageRow(settings.height, settings.threads, [&](const tbb::blocked_range<int>& rows) {
        std::vector<Ray> rays(rowSamples);
        std::vector<SurfaceHit> hits(rowSamples);
        for (int y = rows.begin(); y != rows.end(); ++y) {
            const std::size_t k = rowRays(camera, settings, y, rays);
            tracer.closestSurfaceHits(std::span<const Ray>(rays.data(), k),
                                      std::span<SurfaceHit>(hits.data(), k));
            for (std::size_t i = 0; i < k; ++i) {
                if (shader != nullptr && hits[i].patch != kNoPatch)
                    shader->resolve(rays[i], hits[i]);
                if (hits[i].patch != kNoPatch)
                    hit[hits[i].patch].store(1, std::memory_order_relaxed);
            }
        }
    });
    std::vector<uint8_t> needed(mesh.patchCount(), 0);
    for (uint32_t p = 0; p < mesh.patchCount(); ++p) {
        if (hit[p].load(std::memory_order_relaxed) == 0) continue;
        for (const uint32_t corner : mesh.patches[p]) {
            for (const uint32_t q : mesh.patchesAtVertex(corner))
                needed[q] = 1;
        }
    }
    return needed;
}

}  // namespace daisy
