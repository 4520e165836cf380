#include "radiosity/punctual_lights.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/strings.h"
#include "raycast/ray_caster.h"
#include "spectral/fluorescence.h"

namespace daisy {
namespace {

constexpr int kPointsPerPatch = 4;

// The sample points of patch i: its centroid and the midpoints from it to each corner.
std::array<Vec3d, kPointsPerPatch> samplePoints(const PatchMesh& patches, std::size_t i) {
    const Vec3d c = patches.centroids[i];
    std::array<Vec3d, kPointsPerPatch> points{c, c, c, c};
    for (int k = 0; k < 3; ++k)
        points[k + 1] = (c + patches.positions[patches.patches[i][k]]) * 0.5;
    return points;
}

}  // namespace

double punctualFalloff(const PunctualLight& light, double distance, double cosFromAxis) {
    double falloff = 1;
    if (light.range > 0) {
        // KHR_lights_punctual: clamp(1 - (d / range)^4, 0, 1) windows the inverse square.
        const double ratio = distance / light.range;
        falloff = std::clamp(1 - ratio * ratio * ratio * ratio, 0.0, 1.0);
    }
    if (light.type == PunctualLight::Type::Spot) {
        const double cosOuter = std::cos(light.outerConeRad);
        const double cosInner = std::cos(light.innerConeRad);
        const double scale = 1 / std::max(0.001, cosInner - cosOuter);
        const double t = std::clamp((cosFromAxis - cosOuter) * scale, 0.0, 1.0);
        falloff *= t * t;
    }
    return falloff;
}

Expected<LightGeometry> punctualLightGeometry(const PatchMesh& patches,
                                              const std::vector<PunctualLight>& lights) {
    LightGeometry geometry;
    geometry.lightCount = lights.size();
    const std::size_t n = patches.patchCount(), count = lights.size();
    geometry.factors.assign(n * count, 0);
    if (n == 0 || count == 0) return geometry;
    auto caster = makeRayCaster(patches);
    if (!caster) return withContext(caster.error(), "lights");
    Bounds3d bounds;
    for (const Vec3d& p : patches.positions)
        bounds.extend(p);
    const double far = 4 * std::max(bounds.diagonal(), 1e-9);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const auto& range) {
        SegmentArrays segments;
        std::vector<uint8_t> blocked;
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const Vec3d& normal = patches.normals[i];
            const auto points = samplePoints(patches, i);
            for (std::size_t l = 0; l < count; ++l) {
                const PunctualLight& light = lights[l];
                const bool directional = light.type == PunctualLight::Type::Directional;
                const Vec3d toLight =
                    directional ? -light.direction : light.position - patches.centroids[i];
                const double distance = directional ? 1.0 : length(toLight);
                if (!(distance > 0)) continue;
                const Vec3d unit = toLight / distance;
                const double cosine = dot(normal, unit);
                if (cosine <= 0) continue;  // the light is behind the patch
                double factor = cosine;
                if (!directional) {
                    factor *= punctualFalloff(light, distance, dot(light.direction, -unit)) /
                        (distance * distance);
                }
                if (factor <= 0) continue;
                segments.resize(kPointsPerPatch);
                for (int k = 0; k < kPointsPerPatch; ++k) {
                    const Vec3d& p = points[k];
                    const Vec3d end = directional ? p + unit * far : light.position;
                    segments.set(k, float(p.x), float(p.y), float(p.z), float(end.x), float(end.y),
                                 float(end.z));
                }
                blocked.assign(kPointsPerPatch, 0);
                (*caster)->occluded(segments, blocked);
                int open = 0;
                for (uint8_t b : blocked)
                    open += b == 0;
                geometry.factors[i * count + l] = factor * open / kPointsPerPatch;
            }
        }
    });
    return geometry;
}

Expected<void> addDirectLight(RadiositySystem& system, const LightGeometry& geometry,
                              const std::vector<PunctualLight>& lights, const WavelengthSet& set) {
    const std::size_t m = system.wavelengthCount, count = lights.size();
    if (count == 0) return {};
    // Each light's irradiance at g = 1: its colour x intensity as an RGB emission spectrum.
    std::vector<std::vector<double>> spectra;
    for (const PunctualLight& light : lights) {
        const Rgb rgb{light.color[0] * light.intensity, light.color[1] * light.intensity,
                      light.color[2] * light.intensity};
        std::optional<SpectrumSpec> spectral = light.spectrum;
        if (spectral) spectral->scale *= light.intensity;
        auto spectrum = materialEmission(set, spectral, rgb, concat("light '", light.name, "'"));
        if (!spectrum) return spectrum.error();
        spectra.push_back(std::move(*spectrum));
    }
    std::vector<double> irradiance(m);
    for (uint32_t i = 0; i < system.patchCount; ++i) {
        std::fill(irradiance.begin(), irradiance.end(), 0.0);
        bool lit = false;
        for (std::size_t l = 0; l < count; ++l) {
            const double g = geometry.factors[std::size_t(i) * count + l];
            if (g <= 0) continue;
            lit = true;
            for (std::size_t k = 0; k < m; ++k)
                irradiance[k] += g * spectra[l][k];
        }
        if (!lit) continue;
        double* e = system.emission.data() + std::size_t(i) * m;
        applyOperator(system.operators[system.patchOperator[i]], irradiance.data(), e, e);
    }
    return {};
}

}  // namespace daisy
