#include "pathtrace/path_tracer.h"

#include <tbb/blocked_range.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/check.h"
#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "geometry/patch_mesh.h"
#include "image/camera.h"
#include "image/pixel_samples.h"
#include "image/texture_detail.h"
#include "radiosity/punctual_lights.h"
#include "radiosity/radiosity_system.h"
#include "raycast/ray_caster.h"
#include "shared/rng.h"

namespace daisy {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kRouletteStart = 3;  // bounces before Russian roulette may end a path

// Counter-based uniform numbers for one path: dimension d of the path's stream.
struct PathRandom {
    uint32_t seed;
    uint32_t dimension = 0;
    double next() {
        const uint32_t a = shared::pcgHash(seed ^ shared::pcgHash(dimension++));
        const uint32_t b = shared::pcgHash(a + 0x68e31da4u);
        // 53 bits would be wasted on float geometry; 32 + 21 bits keep the result < 1.
        return (double(a) + double(b >> 11) / 2097152.0) / 4294967296.0;
    }
};

// The emitters' front sides, picked per path vertex x in proportion to a bound-like estimate of
// their contribution there: power / (r^2 + area), r the distance from x to the triangle's
// centroid, and 0 exactly where the triangle cannot light x (x behind its plane, or all of it
// behind x's). By power alone, a point beside one of the black-light box's 176 tube triangles
// drew the far ones as often and met the near ones' 1 / r^2 rarely: fireflies.
// Scenes with many emitter triangles (an exporter's finely tessellated light: 5,184 on the
// double-sided Blender-style Cornell box) pick in two steps so that a vertex costs O(sqrt N),
// not O(N): the entries are ordered along a Morton curve and cut into groups of about sqrt N;
// a group is drawn by the same estimate from its centroid, power and area (never 0, so every
// entry that can light x keeps a chance), then an entry of the group by its own weight. With
// at most kOneGroupEmitters entries there is one group, and the pick is the one-step pick.
constexpr std::size_t kOneGroupEmitters = 256;

struct EmitterTable {
    std::vector<uint32_t> patches;
    std::vector<double> power;  // per entry: sum_k E_k w_k times the area (W)
    std::vector<int> entryOf;  // per patch: its entry, or -1 for non-emitters
    std::size_t groupSize = 1;  // entries a group; group g is [g, g + 1) x groupSize, cut at N
    std::vector<std::size_t> groupStart;  // entries [groupStart[g], groupStart[g + 1])
    std::vector<Vec3d> groupCentroid;  // power-weighted
    std::vector<double> groupPower, groupArea;

    // What one vertex drew: the entry and its probability, or none (total 0).
    struct Pick {
        std::size_t entry = 0;
        double probability = 0;  // 0: nothing drawn (no entry of the group can light x)
        double groupEntryTotal = 0;  // the drawn group's entry weights' total
    };

    double weight(const PatchMesh& mesh, std::size_t k, const Vec3d& x, const Vec3d& n) const {
        const uint32_t q = patches[k];
        const Vec3d d = mesh.centroids[q] - x;
        if (dot(mesh.normals[q], d) >= 0) return 0;  // x behind (or in) the light's plane
        const auto& c = mesh.patches[q];
        if (dot(n, mesh.positions[c[0]] - x) <= 0 && dot(n, mesh.positions[c[1]] - x) <= 0 &&
            dot(n, mesh.positions[c[2]] - x) <= 0) {
            return 0;  // all of the light behind x's surface
        }
        return power[k] / (dot(d, d) + mesh.areas[q]);
    }

    double groupWeight(std::size_t g, const Vec3d& x) const {
        const Vec3d d = groupCentroid[g] - x;
        return groupPower[g] / (dot(d, d) + groupArea[g]);
    }

    // Fills `cdf` with the running sum of group g's entry weights at x (normal n), at the
    // entries' own indices; returns their total.
    double entryWeights(const PatchMesh& mesh, std::size_t g, const Vec3d& x, const Vec3d& n,
                        std::vector<double>& cdf) const {
        double total = 0;
        for (std::size_t k = groupStart[g]; k < groupStart[g + 1]; ++k) {
            total += weight(mesh, k, x, n);
            cdf[k] = total;
        }
        return total;
    }

    // Fills `groupCdf` with the running sum of the group weights at x (one group: 1).
    double groupWeights(const Vec3d& x, std::vector<double>& groupCdf) const {
        double total = 0;
        for (std::size_t g = 0; g + 1 < groupStart.size(); ++g) {
            total += groupStart.size() == 2 ? 1.0 : groupWeight(g, x);
            groupCdf[g] = total;
        }
        return total;
    }

    // An entry for u in [0, 1) at x, and its probability; `cdf` and `groupCdf` are scratch.
    Pick pick(const PatchMesh& mesh, const Vec3d& x, const Vec3d& n, double u,
              std::vector<double>& cdf, std::vector<double>& groupCdf) const {
        const std::size_t groups = groupStart.size() - 1;
        const double groupTotal = groupWeights(x, groupCdf);
        const auto g = std::min<std::size_t>(
            std::size_t(std::upper_bound(groupCdf.begin(),
                                         groupCdf.begin() + std::ptrdiff_t(groups),
                                         u * groupTotal) -
                        groupCdf.begin()),
            groups - 1);
        const double below = g == 0 ? 0.0 : groupCdf[g - 1];
        const double groupShare = (groupCdf[g] - below) / groupTotal;
        // u rescaled within the group's interval, for the entry.
        const double v = groups == 1 ? u
                                     : std::clamp((u * groupTotal - below) / (groupCdf[g] - below),
                                                  0.0, std::nextafter(1.0, 0.0));
        const double total = entryWeights(mesh, g, x, n, cdf);
        Pick pick;
        pick.groupEntryTotal = total;
        if (!(total > 0)) return pick;
        const std::size_t first = groupStart[g], last = groupStart[g + 1];
        const auto it = std::upper_bound(cdf.begin() + std::ptrdiff_t(first),
                                         cdf.begin() + std::ptrdiff_t(last), v * total);
        pick.entry = std::min<std::size_t>(std::size_t(it - cdf.begin()), last - 1);
        const double own = pick.entry == first ? cdf[first] : cdf[pick.entry] - cdf[pick.entry - 1];
        pick.probability = groups == 1 ? own / total : groupShare * (own / total);
        return pick;
    }

    // The probability that pick() at x draws `entry` (the indirect ray's MIS weight). With one
    // group its entry total is the pick's there (`oneGroupTotal`), not summed again.
    double probability(const PatchMesh& mesh, std::size_t entry, const Vec3d& x, const Vec3d& n,
                       double oneGroupTotal, std::vector<double>& cdf,
                       std::vector<double>& groupCdf) const {
        if (groupStart.size() == 2)
            return oneGroupTotal > 0 ? weight(mesh, entry, x, n) / oneGroupTotal : 0.0;
        const std::size_t g = entry / groupSize;
        const double total = entryWeights(mesh, g, x, n, cdf);
        if (!(total > 0)) return 0;
        const double groupTotal = groupWeights(x, groupCdf);
        return groupWeight(g, x) / groupTotal * (weight(mesh, entry, x, n) / total);
    }
};

EmitterTable emitterTable(const PatchMesh& mesh, const RadiositySystem& system) {
    EmitterTable table;
    table.entryOf.assign(mesh.patchCount(), -1);
    std::vector<uint32_t> emitting;
    std::vector<double> power;
    for (uint32_t p = 0; p < mesh.patchCount(); ++p) {
        const double* e = system.emissionRow(p);
        double w = 0;
        for (std::size_t k = 0; k < system.wavelengthCount; ++k)
            w += e[k] * system.binWidthsNm[k];
        if (w > 0 && mesh.areas[p] > 0) {
            emitting.push_back(p);
            power.push_back(w * mesh.areas[p]);
        }
    }
    const std::size_t count = emitting.size();
    std::vector<std::size_t> order(count);
    for (std::size_t k = 0; k < count; ++k)
        order[k] = k;
    table.groupSize = std::max<std::size_t>(count, 1);
    if (count > kOneGroupEmitters) {
        // Morton order of the centroids in the emitters' bounding box, 21 bits an axis.
        Vec3d lo = mesh.centroids[emitting[0]], hi = lo;
        for (const uint32_t p : emitting) {
            const Vec3d& c = mesh.centroids[p];
            lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
            hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
        }
        const auto spread = [](uint64_t v) {
            uint64_t r = 0;
            for (int b = 0; b < 21; ++b)
                r |= ((v >> b) & 1u) << (3 * b);
            return r;
        };
        std::vector<uint64_t> code(count);
        for (std::size_t k = 0; k < count; ++k) {
            const Vec3d& c = mesh.centroids[emitting[k]];
            uint64_t key = 0;
            for (int axis = 0; axis < 3; ++axis) {
                const double extent = hi[axis] - lo[axis];
                const double t = extent > 0 ? (c[axis] - lo[axis]) / extent : 0.0;
                key |= spread(uint64_t(std::clamp(t, 0.0, 1.0) * double((1u << 21) - 1))) << axis;
            }
            code[k] = key;
        }
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return code[a] < code[b]; });
        table.groupSize = std::size_t(std::ceil(std::sqrt(double(count))));
    }
    for (std::size_t k = 0; k < count; ++k) {
        const uint32_t p = emitting[order[k]];
        table.entryOf[p] = int(k);
        table.patches.push_back(p);
        table.power.push_back(power[order[k]]);
        if (k % table.groupSize == 0) {
            table.groupStart.push_back(k);
            table.groupCentroid.push_back({0, 0, 0});
            table.groupPower.push_back(0);
            table.groupArea.push_back(0);
        }
        const std::size_t g = table.groupStart.size() - 1;
        table.groupCentroid[g] = table.groupCentroid[g] + mesh.centroids[p] * table.power.back();
        table.groupPower[g] += table.power.back();
        table.groupArea[g] += mesh.areas[p];
    }
    table.groupStart.push_back(count);
    for (std::size_t g = 0; g < table.groupPower.size(); ++g)
        table.groupCentroid[g] = table.groupCentroid[g] / table.groupPower[g];
    return table;
}

// A direction with pdf cos(theta) / pi about unit normal n (Malley's method: a uniform point
// on the unit disk lifted to the hemisphere).
Vec3d cosineSampleHemisphere(const Vec3d& n, double u1, double u2) {
    const Vec3d helper = std::abs(n.x) > 0.5 ? Vec3d{0, 1, 0} : Vec3d{1, 0, 0};
    const Vec3d t = normalize(cross(helper, n));
    const Vec3d b = cross(n, t);
    const double r = std::sqrt(u1);
    const double phi = 2 * kPi * u2;
    const double z = std::sqrt(std::max(0.0, 1 - u1));
    return normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * z);
}

// Veach's power heuristic (Veach & Guibas 1995, "Optimally Combining Sampling Techniques for
// Monte Carlo Rendering"), one sample from each of the two techniques: a^2 / (a^2 + b^2).
double powerHeuristic(double a, double b) {
    return a * a / (a * a + b * b);
}

Ray makeRay(const Vec3d& origin, const Vec3d& direction) {
    Ray ray;
    for (int axis = 0; axis < 3; ++axis) {
        ray.origin[axis] = static_cast<float>(origin[axis]);
        ray.direction[axis] = static_cast<float>(direction[axis]);
    }
    return ray;
}

// The response rows a path carries: row c of the throughput T weighs the radiance leaving the
// current point at sample k by its contribution to the pixel's value c. Values are X, Y, Z
// (rows = the set's XYZ weights), then, for spectral images, the m radiances (unit rows).
// A surface multiplies T by its M on the right: T' = T M (the eye's value is a linear
// function of the radiance at every sample, and fluorescence mixes the samples).
struct Responses {
    std::size_t rows = 0, m = 0;
    std::vector<double> initial;  // rows x m
    double initialTotal = 0;
};

Responses makeResponses(const WavelengthSet& set, bool spectral) {
    Responses r;
    r.m = set.size();
    r.rows = 3 + (spectral ? r.m : 0);
    r.initial.assign(r.rows * r.m, 0.0);
    for (std::size_t k = 0; k < r.m; ++k) {
        for (int c = 0; c < 3; ++c)
            r.initial[std::size_t(c) * r.m + k] = set.xyzWeights(k)[std::size_t(c)];
        if (spectral) r.initial[(3 + k) * r.m + k] = 1;
    }
    for (const double v : r.initial)
        r.initialTotal += v;
    return r;
}

struct Tracer {
    const PatchMesh& mesh;
    const RadiositySystem& system;
    const EmitterTable& emitters;
    const RayCaster& caster;
    const Responses& responses;
    const std::vector<PunctualLight>& lights;
    const std::vector<std::vector<double>>& lightSpectra;  // punctualLightSpectra
    double offset;  // origin offset along the normal, scene units
    double far;  // a length that leaves the scene from anywhere in it, scene units
    int maxBounces;

    // Next-event estimation to every punctual light (a delta light, which no ray can hit): the
    // irradiance c I cos(theta) falloff / d^2 at the surface point (directional: c I cos) behind
    // a shadow ray from x (the point lifted off the surface), times the 1 / pi of the Lambertian
    // reflection. A light too close for d^3 to be a normal double adds nothing.
    template <typename AddEmission>
    void addPunctualLights(const Vec3d& surface, const Vec3d& x, const Vec3d& n,
                           const std::vector<double>& next, SegmentArrays& segment, uint64_t& rays,
                           const AddEmission& addEmission) const {
        for (std::size_t l = 0; l < lights.size(); ++l) {
            Vec3d end;
            const double g = punctualPointFactor(lights[l], surface, n, far, end);
            if (!(g > 0)) continue;
            segment.set(0, float(x.x), float(x.y), float(x.z), float(end.x), float(end.y),
                        float(end.z));
            uint8_t blocked = 0;
            caster.occluded(segment, {&blocked, 1});
            ++rays;
            if (!blocked) addEmission(next, lightSpectra[l].data(), g / kPi);
        }
    }

    // Sets `value` (responses.rows values: X Y Z [L_0 .. L_{m-1}]) to one camera ray's estimate;
    // returns whether it hit. `weight` and `next` are scratch of rows x m. Counts rays in `rays`.
    bool trace(const Ray& cameraRay, PathRandom& random, std::vector<double>& value,
               std::vector<double>& weight, std::vector<double>& next, std::vector<double>& cdf,
               std::vector<double>& groupCdf, SegmentArrays& segment, uint64_t& rays) const {
        const std::size_t m = system.wavelengthCount, rows = responses.rows;
        std::fill(value.begin(), value.end(), 0.0);
        weight = responses.initial;
        const auto addEmission = [&](const std::vector<double>& t, const double* e, double scale) {
            for (std::size_t c = 0; c < rows; ++c) {
                double sum = 0;
                for (std::size_t k = 0; k < m; ++k)
                    sum += t[c * m + k] * e[k];
                value[c] += sum * scale;
            }
        };
        Ray ray = cameraRay;
        SurfaceHit hit{};
        caster.closestSurfaceHits({&ray, 1}, {&hit, 1}, 0.0f);
        ++rays;
        if (hit.patch == kNoPatch) return false;
        resolveBackFace(mesh, ray, hit);
        double previousCos = 1;  // cos at the last vertex of the indirect ray's direction
        Vec3d previousX, previousN;  // the last vertex and its normal
        double previousTotal = 0;  // the drawn group's entry weights' total there (all, with one)
        for (int bounce = 0;; ++bounce) {
            const uint32_t p = hit.patch;
            const Vec3d& n = mesh.normals[p];
            const Vec3d dir{ray.direction[0], ray.direction[1], ray.direction[2]};
            if (dot(dir, n) >= 0) break;  // the back of a one-sided surface: black
            // (A double-sided surface's back face is its back patch, resolved above.)
            if (bounce == 0) {
                addEmission(weight, system.emissionRow(p), 1 / kPi);
            } else if (const int entry = emitters.entryOf[p]; entry >= 0) {
                // The indirect ray found an emitter: its share against next-event estimation
                // of the same point (solid-angle densities of both techniques; the pick
                // probability as the last vertex drew it).
                const double pick = emitters.probability(mesh, std::size_t(entry), previousX,
                                                         previousN, previousTotal, cdf, groupCdf);
                const double cosY = -dot(dir, n);
                const double lightPdf = pick / mesh.areas[p] * double(hit.t) * hit.t / cosY;
                addEmission(weight, system.emissionRow(p),
                            powerHeuristic(previousCos / kPi, lightPdf) / kPi);
            }
            const MaterialOperator& op = system.operators[system.patchOperator[p]];
            if (op.isZero) break;
            // next = weight * M: the throughput onto the irradiance at each sample.
            if (op.isDiagonal) {
                for (std::size_t c = 0; c < rows; ++c) {
                    for (std::size_t k = 0; k < m; ++k)
                        next[c * m + k] = weight[c * m + k] * op.diagonal[k];
                }
            } else {
                std::fill(next.begin(), next.end(), 0.0);
                for (std::size_t c = 0; c < rows; ++c)
                    addTransposedOperator(op, weight.data() + c * m, next.data() + c * m);
            }
            const auto& c = mesh.patches[p];
            const double w1 = hit.u, w2 = hit.v, w0 = 1 - w1 - w2;
            const Vec3d surface =
                mesh.positions[c[0]] * w0 + mesh.positions[c[1]] * w1 + mesh.positions[c[2]] * w2;
            const Vec3d x = surface + n * offset;

            // Direct light: one emitter point, the emitter drawn by its weight at x.
            const double uPick = random.next();
            EmitterTable::Pick drawn;
            if (!emitters.patches.empty()) drawn = emitters.pick(mesh, x, n, uPick, cdf, groupCdf);
            if (drawn.probability > 0) {
                const std::size_t entry = drawn.entry;
                const uint32_t q = emitters.patches[entry];
                const double pick = drawn.probability;
                const auto& lc = mesh.patches[q];
                double a = random.next(), b = random.next();
                if (a + b > 1) a = 1 - a, b = 1 - b;
                const Vec3d& nq = mesh.normals[q];
                const Vec3d y = mesh.positions[lc[0]] * (1 - a - b) + mesh.positions[lc[1]] * a +
                    mesh.positions[lc[2]] * b + nq * offset;
                const Vec3d d = y - x;
                const double r2 = dot(d, d);
                if (r2 > 0) {
                    const Vec3d u = d / std::sqrt(r2);
                    const double cosX = dot(n, u), cosY = -dot(nq, u);
                    if (cosX > 0 && cosY > 0 && q != p) {
                        segment.set(0, float(x.x), float(x.y), float(x.z), float(y.x), float(y.y),
                                    float(y.z));
                        uint8_t blocked = 0;
                        caster.occluded(segment, {&blocked, 1});
                        ++rays;
                        // E / pi * G / pdf_area, pdf_area = pick / area; then the 1 / pi of
                        // the Lambertian reflection; times its MIS weight against the indirect
                        // ray (pdf cos_x / pi) finding the same point.
                        if (!blocked) {
                            const double lightPdf = pick / mesh.areas[q] * r2 / cosY;
                            addEmission(next, system.emissionRow(q),
                                        cosX * cosY / r2 * mesh.areas[q] / pick / (kPi * kPi) *
                                            powerHeuristic(lightPdf, cosX / kPi));
                        }
                    }
                }
            }

            addPunctualLights(surface, x, n, next, segment, rays, addEmission);

            if (bounce + 1 >= maxBounces) break;
            double survive = 1;
            if (bounce + 1 >= kRouletteStart) {
                double total = 0;
                for (const double v : next)
                    total += v;
                survive = std::min(1.0, total / responses.initialTotal);
                if (survive <= 0 || random.next() >= survive) break;
            }
            for (std::size_t i = 0; i < next.size(); ++i)
                weight[i] = next[i] / survive;
            const double u1 = random.next(), u2 = random.next();
            const Vec3d direction = cosineSampleHemisphere(n, u1, u2);
            previousCos = dot(n, direction);
            previousX = x;
            previousN = n;
            previousTotal = drawn.groupEntryTotal;
            ray = makeRay(x, direction);
            caster.closestSurfaceHits({&ray, 1}, {&hit, 1}, 0.0f);
            ++rays;
            if (hit.patch == kNoPatch) break;
            resolveBackFace(mesh, ray, hit);
        }
        return true;
    }
};

}  // namespace

double relativeRmsNoise(const Image& image, int yChannel, const Image& varianceY,
                        const std::vector<uint8_t>& mask) {
    double sumVariance = 0, sumY = 0;
    std::size_t count = 0;
    const std::size_t pixels = std::size_t(image.width) * image.height;
    for (std::size_t i = 0; i < pixels; ++i) {
        const bool use =
            mask.empty() ? image.pixels[i * image.channels + yChannel + 2] > 0 : mask[i] != 0;
        if (!use) continue;
        sumVariance += varianceY.pixels[i];
        sumY += image.pixels[i * image.channels + yChannel];
        ++count;
    }
    if (count == 0 || sumY <= 0) return 0;
    return std::sqrt(sumVariance / double(count)) / (sumY / double(count));
}

Expected<PathTraceResult> pathTrace(const Scene& scene, const WavelengthSet& set,
                                    const Camera& camera, const PathTraceSettings& settings,
                                    const CancelToken* cancel) {
    const Timer timer;
    if (settings.width <= 0 || settings.height <= 0 || settings.samplesPerPixel <= 0 ||
        settings.maxBounces <= 0) {
        return Error{concat("path trace: image size ", settings.width, " x ", settings.height, ", ",
                            settings.samplesPerPixel, " samples per pixel and ",
                            settings.maxBounces, " bounces must all be positive")};
    }
    if (auto ok = checkRayCamera(camera); !ok) return withContext(ok.error(), "path trace");
    // Double-sided materials' back patches, as the radiosity session makes them: the back face
    // reflects and emits as the front does.
    std::vector<uint8_t> doubleSided(scene.materials.size());
    for (std::size_t m = 0; m < doubleSided.size(); ++m)
        doubleSided[m] = scene.materials[m].doubleSided;
    auto mesh = buildPatchMesh(scene.mesh, 0, UINT32_MAX, doubleSided);
    if (!mesh) return withContext(mesh.error(), "path trace");
    auto system = buildRadiositySystem(scene, *mesh, set);
    if (!system) return withContext(system.error(), "path trace");
    auto caster = makeRayCaster(*mesh, {.packetMode = PacketMode::Single});
    if (!caster) return withContext(caster.error(), "path trace");
    const EmitterTable emitters = emitterTable(*mesh, *system);
    auto lightSpectra = punctualLightSpectra(scene.lights, set);
    if (!lightSpectra) return withContext(lightSpectra.error(), "path trace");

    double extent = 0;
    for (const Vec3d& v : mesh->positions)
        extent = std::max({extent, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    const Responses responses = makeResponses(set, settings.spectral);
    const Tracer tracer{*mesh,
                        *system,
                        emitters,
                        **caster,
                        responses,
                        scene.lights,
                        *lightSpectra,
                        1e-5 * std::max(extent, 1e-3),
                        4 * std::max(extent, 1e-3),
                        settings.maxBounces};

    const std::size_t m = set.size();
    const int channels = int(m) * (settings.spectral ? 1 : 0) + 4;
    const int xyzChannel = settings.spectral ? int(m) : 0;
    PathTraceResult result;
    result.image = Image(settings.width, settings.height, channels);
    result.varianceY = Image(settings.width, settings.height, 1);
    const int side = samplesPerSide(settings.samplesPerPixel);
    const int n = settings.samplesPerPixel;
    const uint32_t imageSeed = shared::pcgHash(settings.seed ^ 0x5bd1e995u);
    std::atomic<uint64_t> rayCount{0};
    std::atomic<bool> stopped{false};
    Progress progress("path trace", uint64_t(settings.height), "rows",
                      settings.showProgress && progressEnabledByDefault());

    const auto renderRows = [&](const tbb::blocked_range<int>& rows) {
        const std::size_t rowsCarried = responses.rows;
        std::vector<double> value(rowsCarried), weight(rowsCarried * m), next(rowsCarried * m);
        std::vector<double> sum(rowsCarried), cdf(emitters.patches.size());
        std::vector<double> groupCdf(emitters.groupPower.size());
        SegmentArrays segment;
        segment.resize(1);
        uint64_t rays = 0;
        for (int y = rows.begin(); y != rows.end(); ++y) {
            if (isCancelled(cancel)) {
                stopped = true;
                break;
            }
            for (int x = 0; x < settings.width; ++x) {
                const uint32_t pixel = uint32_t(y) * uint32_t(settings.width) + uint32_t(x);
                const uint32_t pixelSeed = shared::pcgHash(imageSeed ^ shared::pcgHash(pixel));
                std::fill(sum.begin(), sum.end(), 0.0);
                double sumY2 = 0, hits = 0;
                for (int s = 0; s < n; ++s) {
                    PathRandom random{shared::pcgHash(pixelSeed + uint32_t(s) * 0x9e3779b9u)};
                    const double ju = random.next(), jv = random.next();
                    const auto [ox, oy] = stratumOffset(s, side, ju, jv);
                    const Ray ray =
                        primaryRay(camera, settings.width, settings.height, x + ox, y + oy);
                    if (!tracer.trace(ray, random, value, weight, next, cdf, groupCdf, segment,
                                      rays))
                        continue;
                    hits += 1;
                    for (std::size_t c = 0; c < rowsCarried; ++c)
                        sum[c] += value[c];
                    sumY2 += value[1] * value[1];
                }
                // Responses are X Y Z [L...]; the image is [L...] X Y Z coverage.
                float* out = result.image.at(x, y);
                for (std::size_t k = 3; k < rowsCarried; ++k)
                    out[k - 3] = static_cast<float>(sum[k] / n);
                for (int c = 0; c < 3; ++c)
                    out[xyzChannel + c] = static_cast<float>(sum[std::size_t(c)] / n);
                out[xyzChannel + 3] = static_cast<float>(hits / n);
                const double sumY = sum[1];
                // Misses are samples of value 0: the variance counts them.
                const double mean = sumY / n;
                const double sampleVariance =
                    n > 1 ? std::max(0.0, (sumY2 - n * mean * mean) / (n - 1)) : 0.0;
                *result.varianceY.at(x, y) = static_cast<float>(sampleVariance / n);
            }
            progress.advance(1);
        }
        rayCount += rays;
    };
    forEachImageRow(settings.height, settings.threads, renderRows);
    progress.finish();
    result.cancelled = stopped;
    result.paths = uint64_t(settings.width) * settings.height * uint64_t(n);
    result.rays = rayCount;
    result.relativeNoise = relativeRmsNoise(result.image, xyzChannel + 1, result.varianceY);
    result.seconds = timer.seconds();
    return result;
}

}  // namespace daisy
