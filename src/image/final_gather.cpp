#include "image/final_gather.h"

#include <tbb/blocked_range.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "backend/embree_ray_caster.h"
#include "core/check.h"
#include "core/strings.h"
#include "image/camera.h"
#include "image/emitter_lights.h"
#include "image/pixel_samples.h"
#include "shared/formfactor.h"
#include "shared/rng.h"
#include "shared/sampling.h"

namespace daisy {

namespace {

constexpr double kPi = std::numbers::pi;

shared::vec3 toVec3(const Vec3d& v) {
    return {float(v.x), float(v.y), float(v.z)};
}

bool emits(const RadiositySystem& system, uint32_t patch) {
    const double* e = system.emissionRow(patch);
    return std::any_of(e, e + system.wavelengthCount, [](double v) { return v > 0; });
}

// One emitting source triangle: its geometry, its emission E (m values) and its power per unit
// area, sum_k E_k w_k (W m^-2).
struct Light {
    shared::PatchGeometry geometry;
    const double* emission;
    double power;
};

// The emitting source triangles of the scene, coplanar faces merged (image/emitter_lights.h).
std::vector<Light> lightsOf(const Scene& scene, const PatchMesh& patches,
                            const RadiositySystem& system) {
    std::vector<uint32_t> triangles, emissionClass;
    std::vector<uint32_t> patchOf(scene.mesh.triangleCount(), kNoPatch);
    std::map<std::vector<double>, uint32_t> classes;
    for (uint32_t p = 0; p < patches.patchCount(); ++p) {
        const uint32_t t = patches.sourceTriangle[p];
        if (patchOf[t] != kNoPatch || !emits(system, p)) continue;
        patchOf[t] = p;
        triangles.push_back(t);
        const double* e = system.emissionRow(p);
        emissionClass.push_back(
            classes.emplace(std::vector<double>(e, e + system.wavelengthCount), classes.size())
                .first->second);
    }
    std::vector<Light> lights;
    for (const LightTriangle& light : mergeEmitterFaces(scene.mesh, triangles, emissionClass)) {
        const double* emission = system.emissionRow(patchOf[light.sourceTriangle]);
        double power = 0;
        for (std::size_t k = 0; k < system.wavelengthCount; ++k)
            power += emission[k] * system.binWidthsNm[k];
        lights.push_back(
            {shared::makePatchGeometry(toVec3(light.corners[0]), toVec3(light.corners[1]),
                                       toVec3(light.corners[2])),
             emission, power});
    }
    return lights;
}

// Point `index` of `count` stratified on the part of light triangle t in front of the plane
// through x with normal n (the part F(x -> t) counts): the whole triangle when it lies in
// front, else its clipped polygon (a triangle or a quad: two triangles chosen by area). Points
// behind the plane would be shadowed by x's own surface and darken grazing receivers.
shared::vec3 pointInFront(const shared::PatchGeometry& t, shared::vec3 x, shared::vec3 n,
                          uint32_t seed, int index, int count) {
    if (dot(n, t.a - x) >= 0 && dot(n, t.b - x) >= 0 && dot(n, t.c - x) >= 0)
        return shared::stratifiedPointOnTriangle(seed, index, count, t);
    const shared::ClippedPolygon poly = shared::clipTriangleToHalfSpace(t.a, t.b, t.c, x, n);
    if (poly.count < 3) return shared::stratifiedPointOnTriangle(seed, index, count, t);
    const shared::PatchGeometry first = shared::makePatchGeometry(poly.v[0], poly.v[1], poly.v[2]);
    if (poly.count == 3 || !(first.area > 0))
        return shared::stratifiedPointOnTriangle(seed, index, count, first);
    const shared::PatchGeometry second = shared::makePatchGeometry(poly.v[0], poly.v[2], poly.v[3]);
    const float share = first.area / (first.area + second.area);
    const bool inFirst = shared::hashToUnitFloat(uint32_t(index), seed ^ 0x85ebca6bu) < share;
    return shared::stratifiedPointOnTriangle(seed, index, count, inFirst ? first : second);
}

// Fraction of a shadow segment left out at the light's end (Embree's own margin is 1e-5).
constexpr float kLightClearance = 1e-3f;

// Lights up to which every light's exact factor weighs every sample's shadow segments.
constexpr std::size_t kExactLightLimit = 32;

// A cheap stand-in for F(x -> t) that is > 0 wherever F is: the point-source factor
// A cos_x cos_t / (pi (r^2 + A)) from t's centroid (r^2 + A keeps it finite near the light),
// cos_x the largest over t's corners and centroid, plus a floor of 1e-3 of the cosine-free
// term so a light seen only at grazing angles keeps a chance. 0 when x is behind t's plane or
// all of t behind x's.
float approximateFactor(const shared::PatchGeometry& t, shared::vec3 x, shared::vec3 n) {
    const shared::vec3 centroid = (t.a + t.b + t.c) * (1.0f / 3.0f);
    const shared::vec3 d = centroid - x;
    const float r2 = dot(d, d);
    const float facing = -dot(t.normal, d);
    if (facing <= 0 || r2 <= 0) return 0;
    float cosX = -1;
    for (const shared::vec3 v : {t.a, t.b, t.c, centroid}) {
        const shared::vec3 e = v - x;
        const float l = length(e);
        if (l > 0) cosX = std::max(cosX, dot(n, e) / l);
    }
    if (cosX <= 0) return 0;
    const float cosT = facing / std::sqrt(r2);
    const float base = t.area / (float(kPi) * (r2 + t.area));
    return base * (cosX * cosT + 1e-3f);
}

}  // namespace

std::vector<double> radiosityWithoutDirectLight(const RadiositySystem& system,
                                                const SparseMatrix& formFactors,
                                                std::span<const double> radiosity) {
    const std::size_t n = system.patchCount, m = system.wavelengthCount;
    DAISY_CHECK(radiosity.size() == n * m && formFactors.size == n);
    std::vector<bool> emitter(n);
    for (uint32_t j = 0; j < n; ++j)
        emitter[j] = emits(system, j);
    std::vector<double> out(radiosity.begin(), radiosity.end());
    std::vector<double> direct(m);
    for (uint32_t i = 0; i < n; ++i) {
        const MaterialOperator& op = system.operators[system.patchOperator[i]];
        if (op.isZero) continue;
        std::fill(direct.begin(), direct.end(), 0.0);
        bool any = false;
        const auto columns = formFactors.rowColumns(i);
        const auto values = formFactors.rowValues(i);
        for (std::size_t e = 0; e < columns.size(); ++e) {
            if (!emitter[columns[e]]) continue;
            any = true;
            const double* ej = system.emissionRow(columns[e]);
            for (std::size_t k = 0; k < m; ++k)
                direct[k] += double(values[e]) * ej[k];
        }
        if (!any) continue;
        for (std::size_t o = 0; o < m; ++o) {
            double reflected = 0;
            for (std::size_t k = 0; k < m; ++k)
                reflected += op.matrix(o, k) * direct[k];
            out[i * m + o] -= reflected;
        }
    }
    return out;
}

std::vector<float> radiosityChannels(const WavelengthSet& set, std::span<const double> b,
                                     bool spectral) {
    const std::size_t m = set.size(), n = b.size() / m;
    const std::size_t channels = (spectral ? m : 0) + 4;
    std::vector<float> values(n * channels);
    std::vector<double> radiance(m);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t k = 0; k < m; ++k)
            radiance[k] = b[i * m + k] / kPi;
        float* out = values.data() + i * channels;
        if (spectral) {
            for (std::size_t k = 0; k < m; ++k)
                *out++ = static_cast<float>(radiance[k]);
        }
        const Xyz xyz = set.toXyz(radiance);
        *out++ = static_cast<float>(xyz[0]);
        *out++ = static_cast<float>(xyz[1]);
        *out++ = static_cast<float>(xyz[2]);
        *out = 1.0f;
    }
    return values;
}

Expected<Image> renderDirectLight(const Scene& scene, const PatchMesh& patches,
                                  const RadiositySystem& system, const WavelengthSet& set,
                                  const Camera& camera, const RenderSettings& settings,
                                  const DirectLightSettings& direct, bool spectral,
                                  const SampleShader* shader, const NearField* nearField) {
    if (settings.width <= 0 || settings.height <= 0 || settings.samplesPerPixel <= 0 ||
        direct.shadowRays <= 0) {
        return Error{concat("final gather: image size ", settings.width, " x ", settings.height,
                            ", ", settings.samplesPerPixel, " samples per pixel and ",
                            direct.shadowRays, " shadow rays must all be positive")};
    }
    if (auto ok = checkRayCamera(camera); !ok) return withContext(ok.error(), "final gather");
    // Robust like the renderer's, so both see the same surface at every sample.
    auto caster = EmbreeRayCaster::create(patches, PacketMode::Packet16, /*robust=*/true);
    if (!caster) return withContext(caster.error(), "final gather");
    const EmbreeRayCaster& tracer = **caster;
    const std::vector<Light> lights = lightsOf(scene, patches, system);

    const std::size_t m = set.size();
    const int channels = int(spectral ? m : 0) + 4;
    const int xyzChannel = spectral ? int(m) : 0;
    Image image(settings.width, settings.height, channels);
    const bool gatherNear = nearField != nullptr && !nearField->empty();
    if (lights.empty() && !gatherNear) return image;
    if (!settings.pixelSides.empty() &&
        settings.pixelSides.size() != std::size_t(settings.width) * settings.height) {
        return Error{concat("final gather: ", settings.pixelSides.size(),
                            " per-pixel sample counts for ", settings.width, " x ", settings.height,
                            " pixels")};
    }
    int minSide = samplesPerSide(settings.samplesPerPixel), maxSide = minSide;
    if (!settings.pixelSides.empty()) {
        const auto [lo, hi] =
            std::minmax_element(settings.pixelSides.begin(), settings.pixelSides.end());
        minSide = std::max(1, int(*lo));
        maxSide = int(*hi);
    }
    const std::size_t rowSamples = std::size_t(settings.width) * maxSide * maxSide;
    // --gather-rays is per pixel: shared out over its samples, at least one each; each sample
    // draws its segments over all lights.
    const auto raysPerSample = [&](int samples) {
        return std::max(1, (direct.shadowRays + samples - 1) / samples);
    };
    const int maxK = raysPerSample(minSide * minSide);
    const uint32_t imageSeed = shared::pcgHash(direct.seed ^ 0x2545f491u);
    // Few lights: the exact factor of each, per sample. Many (over kExactLightLimit after the
    // faces are merged): a cheap approximation picks the lights and only the picked ones get
    // the exact factor.
    const bool exactWeights = lights.size() <= kExactLightLimit;

    const auto renderRows = [&](const tbb::blocked_range<int>& rows) {
        std::vector<Ray> rays(rowSamples);
        std::vector<SurfaceHit> hits(rowSamples);
        SegmentArrays segments;
        segments.resize(std::size_t(maxK));
        std::vector<uint8_t> blocked(segments.size());
        std::vector<float> factor(lights.size());
        std::vector<double> cdf(lights.size());
        std::vector<int> picks(lights.size());
        std::vector<uint32_t> chosen(static_cast<std::size_t>(maxK));
        std::vector<double> irradiance(m), reflected(m), sum(static_cast<std::size_t>(channels));
        std::vector<double> sampleValues(std::size_t(xyzChannel) + 3);
        for (int y = rows.begin(); y != rows.end(); ++y) {
            std::size_t r = 0;
            for (int x = 0; x < settings.width; ++x) {
                const int side = pixelSide(settings, x, y);
                for (int s = 0; s < side * side; ++s) {
                    const auto [ox, oy] = sampleOffset(s, side);
                    rays[r++] = primaryRay(camera, settings.width, settings.height, x + ox, y + oy);
                }
            }
            const std::size_t rowCount = r;
            tracer.closestSurfaceHits(std::span<const Ray>(rays.data(), rowCount),
                                      std::span<SurfaceHit>(hits.data(), rowCount));
            if (shader != nullptr) {
                for (std::size_t i = 0; i < rowCount; ++i) {
                    if (hits[i].patch != kNoPatch) shader->resolve(rays[i], hits[i]);
                }
            }
            r = 0;
            for (int x = 0; x < settings.width; ++x) {
                const int side = pixelSide(settings, x, y);
                const int samples = side * side;
                const int k = raysPerSample(samples);
                std::fill(sum.begin(), sum.end(), 0.0);
                // The pixel's samples share one stratification of the light draw: pick q of
                // sample s takes stratum permute(s k + q) of samples x k (a per-pixel random
                // permutation, so each pick is marginally uniform: unbiased), and a light's
                // points continue one stratified stream across the pixel.
                const uint32_t pixelSeed = shared::pcgHash(
                    imageSeed ^
                    shared::pcgHash(uint32_t(y) * uint32_t(settings.width) + uint32_t(x)));
                std::fill(picks.begin(), picks.end(), 0);
                const int strata = samples * k;
                uint32_t weightsPatch = kNoPatch;  // the patch factor and cdf were made for
                double total = 0;
                for (int s = 0; s < samples; ++s, ++r) {
                    const SurfaceHit& hit = hits[r];
                    if (hit.patch == kNoPatch) continue;
                    const uint32_t p = hit.patch;
                    const MaterialOperator& op = system.operators[system.patchOperator[p]];
                    const Vec3d& n = patches.normals[p];
                    const Vec3d dir{rays[r].direction[0], rays[r].direction[1],
                                    rays[r].direction[2]};
                    if (op.isZero || dot(dir, n) >= 0) continue;  // black, or the back side
                    const auto& c = patches.patches[p];
                    const Vec3d px = patches.positions[c[0]] * (1.0 - hit.u - hit.v) +
                        patches.positions[c[1]] * double(hit.u) +
                        patches.positions[c[2]] * double(hit.v);
                    const shared::vec3 xf = toVec3(px), nf = toVec3(n);
                    // Unoccluded factors, weighted by each light's power: the distribution
                    // the k shadow segments are drawn from (stratified over its CDF).
                    const uint32_t sampleSeed = shared::pcgHash(
                        imageSeed ^
                        shared::pcgHash((uint32_t(y) * uint32_t(settings.width) + uint32_t(x)) *
                                            uint32_t(samples) +
                                        uint32_t(s)));
                    // With approximate weights, the samples of one pixel on one patch share
                    // the distribution of the first of them (a fraction of a pixel away: still
                    // importance sampling, each segment weighted by the exact factor over the
                    // shared weight), so a supersampled edge pixel costs a few light loops,
                    // not one per sample.
                    if (!lights.empty() && (exactWeights || p != weightsPatch)) {
                        total = 0;
                        for (std::size_t l = 0; l < lights.size(); ++l) {
                            factor[l] = exactWeights
                                ? shared::pointToTriangleFactor(xf, nf, lights[l].geometry)
                                : approximateFactor(lights[l].geometry, xf, nf);
                            total += factor[l] > 0 ? double(factor[l]) * lights[l].power : 0.0;
                            cdf[l] = total;
                        }
                        weightsPatch = p;
                    }
                    std::fill(irradiance.begin(), irradiance.end(), 0.0);
                    const double covered =
                        gatherNear ? nearField->addIrradiance(p, hit.u, hit.v, irradiance) : 0.0;
                    const int drawn = total > 0 ? k : 0;
                    segments.resize(std::size_t(drawn));
                    for (int q = 0; q < drawn; ++q) {
                        const uint32_t stratum =
                            shared::permuteIndex(uint32_t(s * k + q), uint32_t(strata), pixelSeed);
                        const double u =
                            (stratum + double(shared::hashToUnitFloat(uint32_t(q), sampleSeed))) /
                            strata * total;
                        const std::size_t l = std::min<std::size_t>(
                            std::size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()),
                            lights.size() - 1);
                        chosen[std::size_t(q)] = uint32_t(l);
                        const shared::vec3 e = pointInFront(
                            lights[l].geometry, xf, nf, shared::streamSeed(pixelSeed, uint32_t(l)),
                            picks[l]++, strata);
                        // Stop short of the light by kLightClearance of the distance, so a
                        // surface the light lies on (a lamp face on its stand) does not block.
                        const shared::vec3 end = e + (xf - e) * kLightClearance;
                        segments.set(std::size_t(q), xf.x, xf.y, xf.z, end.x, end.y, end.z);
                    }
                    if (drawn > 0)
                        tracer.occluded(segments,
                                        std::span<uint8_t>(blocked.data(), std::size_t(drawn)));
                    // H = sum_l E_l F_l V_l, each segment an estimate of E_l F_l / p_l with
                    // p_l = F_l P_l / total: E_l total / (P_l k) when open.
                    for (int q = 0; q < drawn; ++q) {
                        if (blocked[std::size_t(q)]) continue;
                        const uint32_t l = chosen[std::size_t(q)];
                        const Light& light = lights[l];
                        // With approximate weights, the chosen light's exact factor over its
                        // weight (importance sampling); with exact ones that ratio is 1.
                        const double ratio = exactWeights
                            ? 1.0
                            : double(shared::pointToTriangleFactor(xf, nf, light.geometry)) /
                                double(factor[l]);
                        const double scale = ratio * total / (light.power * k);
                        for (std::size_t w = 0; w < m; ++w)
                            irradiance[w] += light.emission[w] * scale;
                    }
                    applyOperator(op, irradiance.data(), reflected.data());
                    for (double& v : reflected)
                        v /= kPi;
                    if (spectral)
                        std::copy(reflected.begin(), reflected.end(), sampleValues.begin());
                    const Xyz xyz = set.toXyz(reflected);
                    for (int a = 0; a < 3; ++a)
                        sampleValues[std::size_t(xyzChannel + a)] = xyz[std::size_t(a)];
                    if (covered > 0) nearField->removeCovered(hit, covered, sampleValues);
                    if (shader != nullptr) shader->shade(hit, sampleValues);
                    for (std::size_t v = 0; v < sampleValues.size(); ++v)
                        sum[v] += sampleValues[v];
                }
                float* out = image.at(x, y);
                for (int ch = 0; ch < channels; ++ch)
                    out[ch] = static_cast<float>(sum[std::size_t(ch)] / samples);
            }
        }
    };
    forEachImageRow(settings.height, settings.threads, renderRows);
    return image;
}

}  // namespace daisy
