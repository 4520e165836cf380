#include "image/edge_sampling.h"

#include <tbb/blocked_range.h>

#include <algorithm>
#include <cmath>

#include "core/strings.h"
#include "image/camera.h"
#include "image/pixel_samples.h"
#include "raycast/ray_caster.h"

namespace daisy {

namespace {

struct CentreHit {
    uint32_t patch = kNoPatch;
    Vec3d point;
    double distance = 0;
};

bool sameSurface(const PatchMesh& mesh, const CentreHit& a, const CentreHit& b) {
    if ((a.patch == kNoPatch) != (b.patch == kNoPatch)) return false;
    if (a.patch == kNoPatch) return true;
    if (a.patch == b.patch) return true;
    if (mesh.materials[a.patch] != mesh.materials[b.patch]) return false;
    const Vec3d& na = mesh.normals[a.patch];
    const Vec3d& nb = mesh.normals[b.patch];
    if (dot(na, nb) < kEdgeCreaseCosine) return false;
    const double offA = std::abs(dot(na, b.point - a.point));
    const double offB = std::abs(dot(nb, a.point - b.point));
    return offA <= kEdgeDepthFraction * a.distance && offB <= kEdgeDepthFraction * b.distance;
}

}  // namespace

Expected<std::vector<uint8_t>> edgeAdaptiveSides(const PatchMesh& mesh, const Camera& camera,
                                                 const RenderSettings& settings,
                                                 int edgeSamplesPerPixel,
                                                 const SampleShader* shader) {
    const int w = settings.width, h = settings.height;
    if (w <= 0 || h <= 0 || settings.samplesPerPixel <= 0 || edgeSamplesPerPixel < 0) {
        return Error{concat("edge sampling: image size ", w, " x ", h, ", ",
                            settings.samplesPerPixel, " and ", edgeSamplesPerPixel,
                            " samples per pixel must be positive")};
    }
    const int base = samplesPerSide(settings.samplesPerPixel);
    const int edge = std::max(base, samplesPerSide(edgeSamplesPerPixel));
    if (edge > 255) {
        return Error{concat("edge sampling: ", edge, " x ", edge,
                            " samples per pixel is over the limit of 255 x 255")};
    }
    if (auto ok = checkRayCamera(camera); !ok) return withContext(ok.error(), "edge sampling");
    auto caster = makeRayCaster(mesh, {.packetMode = PacketMode::Packet16, .robust = true});
    if (!caster) return withContext(caster.error(), "edge sampling");
    const RayCaster& tracer = **caster;

    std::vector<CentreHit> centres(std::size_t(w) * h);
    forEachImageRow(h, settings.threads, [&](const tbb::blocked_range<int>& rows) {
        std::vector<Ray> rays(static_cast<std::size_t>(w));
        std::vector<SurfaceHit> hits(static_cast<std::size_t>(w));
        for (int y = rows.begin(); y != rows.end(); ++y) {
            for (int x = 0; x < w; ++x) {
                const auto [ox, oy] = sampleOffset(0, 1);
                rays[std::size_t(x)] = primaryRay(camera, w, h, x + ox, y + oy);
            }
            tracer.closestSurfaceHits(rays, hits);
            for (int x = 0; x < w; ++x) {
                SurfaceHit& hit = hits[std::size_t(x)];
                const Ray& ray = rays[std::size_t(x)];
                if (shader != nullptr && hit.patch != kNoPatch) shader->resolve(ray, hit);
                CentreHit& c = centres[std::size_t(y) * w + x];
                c.patch = hit.patch;
                if (hit.patch == kNoPatch) continue;
                const Vec3d origin{ray.origin[0], ray.origin[1], ray.origin[2]};
                const Vec3d dir{ray.direction[0], ray.direction[1], ray.direction[2]};
                c.point = origin + dir * double(hit.t);
                c.distance = double(hit.t) * std::sqrt(dot(dir, dir));
            }
        }
    });

    std::vector<uint8_t> sides(centres.size(), uint8_t(base));
    if (edge == base) return sides;
    forEachImageRow(h, settings.threads, [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
            for (int x = 0; x < w; ++x) {
                const CentreHit& c = centres[std::size_t(y) * w + x];
                bool boundary = false;
                for (int dy = -1; dy <= 1 && !boundary; ++dy) {
                    for (int dx = -1; dx <= 1 && !boundary; ++dx) {
                        const int nx = x + dx, ny = y + dy;
                        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                        boundary = !sameSurface(mesh, c, centres[std::size_t(ny) * w + nx]);
                    }
                }
                if (boundary) sides[std::size_t(y) * w + x] = uint8_t(edge);
            }
        }
    });
    return sides;
}

}  // namespace daisy
