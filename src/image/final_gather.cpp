#include "image/final_gather.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <span>

#include "core/check.h"
#include "core/strings.h"
#include "geometry/shared_vec.h"
#include "image/camera.h"
#include "image/emitter_lights.h"
#include "image/pixel_samples.h"
#include "radiosity/hybrid_far_field.h"
#include "radiosity/punctual_lights.h"
#include "raycast/ray_caster.h"
#include "shared/formfactor.h"
#include "shared/rng.h"
#include "shared/sampling.h"

namespace daisy {

namespace {

constexpr double kPi = std::numbers::pi;

bool emits(std::span<const double> emission, std::size_t m, uint32_t patch) {
    const double* e = emission.data() + std::size_t(patch) * m;
    return std::any_of(e, e + m, [](double v) { return v > 0; });
}

// One emitting source triangle: its geometry, its emission E (m values) and its power per unit
// area, sum_k E_k w_k (W m^-2).
struct Light {
    shared::PatchGeometry geometry;
    const double* emission;
    double power;
    uint32_t spectrum;  // lights with equal emission share it: 0, 1, ... in order of appearance
    uint32_t group;  // its coplanar group (LightTriangle::group), numbered over both sides
};

// The emitting faces of the scene, coplanar faces merged (image/emitter_lights.h); `emission`
// is ownEmission(system), which the lights point into. A double-sided emitter's back patch
// emits too (as the solve has it): its lights are the same merged faces with their corners
// reversed. Without them a Blender-style emissive panel whose front faced away from the room
// lit the smooth solution but not the gathered image (a hall lit through windows by such
// panels came out 40% darker than the path tracer).
std::vector<Light> lightsOf(const Scene& scene, const PatchMesh& patches,
                            const RadiositySystem& system, std::span<const double> emission) {
    const std::size_t m = system.wavelengthCount;
    std::map<std::vector<double>, uint32_t> classes;
    std::vector<Light> lights;
    uint32_t groups = 0;  // the front faces' groups, then the backs'
    for (const bool back : {false, true}) {
        std::vector<uint32_t> triangles, emissionClass;
        std::vector<uint32_t> patchOf(scene.mesh.triangleCount(), kNoPatch);
        std::vector<uint32_t> classOf(scene.mesh.triangleCount(), 0);
        for (uint32_t p = 0; p < patches.patchCount(); ++p) {
            const uint32_t twin = patches.backPatch[p];
            const bool isBack = twin != kNoBackPatch && twin < p;  // backs follow all fronts
            const uint32_t t = patches.sourceTriangle[p];
            if (isBack != back || patchOf[t] != kNoPatch || !emits(emission, m, p)) continue;
            patchOf[t] = p;
            triangles.push_back(t);
            const double* e = emission.data() + std::size_t(p) * m;
            emissionClass.push_back(
                classes.emplace(std::vector<double>(e, e + m), classes.size()).first->second);
            classOf[t] = emissionClass.back();
        }
        const uint32_t firstGroup = groups;
        for (const LightTriangle& light : mergeEmitterFaces(scene.mesh, triangles, emissionClass)) {
            const double* e = emission.data() + std::size_t(patchOf[light.sourceTriangle]) * m;
            double power = 0;
            for (std::size_t k = 0; k < m; ++k)
                power += e[k] * system.binWidthsNm[k];
            const Vec3d& b = light.corners[back ? 2 : 1];
            const Vec3d& c = light.corners[back ? 1 : 2];
            lights.push_back(
                {shared::makePatchGeometry(toVec3(light.corners[0]), toVec3(b), toVec3(c)), e,
                 power, classOf[light.sourceTriangle], firstGroup + light.group});
            groups = std::max(groups, firstGroup + light.group + 1);
        }
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

// Fraction of a shadow segment left out at the light's end (the ray caster's own margin is 1e-5).
constexpr float kLightClearance = 1e-3f;

// Lights up to which every light's exact factor weighs every sample's shadow segments.
constexpr std::size_t kExactLightLimit = 32;

// The segments drawn to one light from one sample (renderDirectLight).
struct LightTally {
    int segments = 0, open = 0;
    double kernel = 0, openKernel = 0;  // sums of pointKernel over them, and over the open ones
};

// The point-to-point kernel cos_x cos_e / r^2 between receiver x (normal n) and light point e
// (light normal ln), up to the factor 1 / pi; 0 where either cosine is not positive.
float pointKernel(shared::vec3 x, shared::vec3 n, shared::vec3 ln, shared::vec3 e) {
    const shared::vec3 d = e - x;
    const float r2 = dot(d, d);
    const float cx = dot(n, d), ce = -dot(ln, d);
    return cx > 0 && ce > 0 && r2 > 0 ? cx * ce / (r2 * r2) : 0.0f;
}

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

// The lights the draw picks as one: with the stand-in's weights (over kExactLightLimit lights),
// a run of kLightGroupMinimum to kLightGroupMaximum consecutive lights of one coplanar group of
// one emission (Light::group), drawn by groupFactor for the whole run and then a light in it by
// area; with the exact factors, each light alone. A lamp's disc, a fan of about 200 triangles
// after merging, then takes 7 stand-ins a sample instead of 200 (the 250,002-triangle
// interior's 972 lights are 77 draws).
// Shorter runs are drawn light by light: the area pick ignores how F varies over the run, which
// took the spread of 36 squares of 2 triangles each (the test of many lights) from 0.036% to
// 0.24%, while a run of 2 saves next to nothing in the loop. Longer ones are cut (slices of the
// fan): on that interior whole discs left 1.78% noise in the image where the lights one by one
// left 1.33% and runs of 32 1.48%, at the same speed (the error against the path tracer less,
// in quadrature, the error at 4 times the segments).
constexpr uint32_t kLightGroupMinimum = 8;
constexpr uint32_t kLightGroupMaximum = 32;

struct LightGroup {
    uint32_t first = 0, count = 0;  // lights [first, first + count)
    shared::vec3 centroid;  // area-weighted: in the group's plane
    float radius = 0;  // of a sphere about the centroid holding every corner
    float area = 0;
};

struct LightGroups {
    std::vector<LightGroup> groups;
    // Per light: the area of its group's lights up to and including it, over the group's.
    std::vector<float> areaCdf;
};

LightGroups lightGroups(const std::vector<Light>& lights, bool byGroup) {
    LightGroups out;
    out.areaCdf.resize(lights.size(), 1.0f);
    for (uint32_t l = 0; l < lights.size();) {
        uint32_t end = l + 1;
        while (byGroup && end < lights.size() && lights[end].group == lights[l].group &&
               end - l < kLightGroupMaximum)
            ++end;
        if (end - l < kLightGroupMinimum) end = l + 1;
        out.groups.push_back({l, end - l, {}, 0, 0});
        l = end;
    }
    for (LightGroup& g : out.groups) {
        double area = 0;
        Vec3d centroid{0, 0, 0};
        for (uint32_t l = g.first; l < g.first + g.count; ++l) {
            const shared::PatchGeometry& t = lights[l].geometry;
            area += t.area;
            const shared::vec3 sum = t.a + t.b + t.c;
            centroid = centroid + Vec3d{sum.x, sum.y, sum.z} * (t.area / 3.0);
            out.areaCdf[l] = float(area);
        }
        if (!(area > 0)) continue;
        g.area = float(area);
        g.centroid = toVec3(centroid * (1.0 / area));
        for (uint32_t l = g.first; l < g.first + g.count; ++l) {
            out.areaCdf[l] = l + 1 == g.first + g.count ? 1.0f : float(out.areaCdf[l] / area);
            const shared::PatchGeometry& t = lights[l].geometry;
            for (const shared::vec3 c : {t.a, t.b, t.c})
                g.radius = std::max(g.radius, shared::length(c - g.centroid));
        }
        g.radius *= 1.0f + 1e-5f;  // rounding: every corner strictly inside
    }
    return out;
}

// approximateFactor's stand-in for a group of coplanar lights (normal ln): the point-source
// factor of its area from its centroid, cos_x the largest over the sphere holding the group
// (the angle to the centroid less the sphere's angular radius), so it is > 0 wherever some
// light's F is; 0 when x is behind the group's plane or the whole sphere behind x's.
float groupFactor(const LightGroup& g, shared::vec3 ln, shared::vec3 x, shared::vec3 n) {
    const shared::vec3 d = g.centroid - x;
    const float r2 = dot(d, d);
    const float facing = -dot(ln, d);
    if (facing <= 0 || r2 <= 0) return 0;
    const float r = std::sqrt(r2);
    float cosX = 1;
    if (g.radius < r) {
        const float cosC = dot(n, d) / r;
        const float sinC = std::sqrt(std::max(0.0f, 1 - cosC * cosC));
        const float sinS = g.radius / r, cosS = std::sqrt(1 - sinS * sinS);
        cosX = cosC >= cosS ? 1.0f : cosC * cosS + sinC * sinS;  // cos(angle - angular radius)
    }
    if (cosX <= 0) return 0;
    const float base = g.area / (float(kPi) * (r2 + g.area));
    return base * (cosX * (facing / r) + 1e-3f);
}

// A pixel's shadow marks: for light l, bit 2 (l mod 32) when one of its segments to l was open,
// the next bit when one was blocked.
uint64_t shadowMark(uint32_t light, bool open) {
    return uint64_t(open ? 1 : 2) << (2 * (light % 32));
}

// Per patch, the lights not hidden from it (lightHiddenFrom, image/emitter_lights.h): on the
// black-light box half of its 20 lights are hidden from a typical patch, so a sample's exact
// weights take one batch of SIMD lanes instead of two.
struct PatchLights {
    std::vector<uint32_t> first;  // patch count + 1: patch p's lights are [first[p], first[p + 1])
    std::vector<uint32_t> lights;  // indices into the light list, ascending per patch

    std::span<const uint32_t> of(uint32_t patch) const {
        return std::span(lights).subspan(first[patch], first[patch + 1] - first[patch]);
    }
};

// The receiver as the gather sees it: the patch's corners in float and the normal it passes to
// the factor.
PatchLights lightsSeenByPatches(const PatchMesh& patches, const std::vector<Light>& lights) {
    PatchLights seen;
    seen.first.reserve(patches.patchCount() + 1);
    seen.first.push_back(0);
    for (uint32_t p = 0; p < patches.patchCount(); ++p) {
        const auto& c = patches.patches[p];
        shared::PatchGeometry receiver = shared::makePatchGeometry(toVec3(patches.positions[c[0]]),
                                                                   toVec3(patches.positions[c[1]]),
                                                                   toVec3(patches.positions[c[2]]));
        receiver.normal = toVec3(patches.normals[p]);
        for (uint32_t l = 0; l < lights.size(); ++l) {
            if (!lightHiddenFrom(receiver, lights[l].geometry)) seen.lights.push_back(l);
        }
        seen.first.push_back(uint32_t(seen.lights.size()));
    }
    return seen;
}

// One thread's estimate of H(x) = sum_l E_l F(x -> l) V(x, l) over the lights, sample by sample
// (final_gather.h): the draw of k shadow segments over the lights' distribution, their points,
// the rays and the per-light kernel-weighted visibility.
class LightSampler {
public:
    LightSampler(const std::vector<Light>& lights, const LightGroups& groups,
                 const PatchLights& seen, const std::vector<const double*>& spectra,
                 std::size_t wavelengths, bool exactWeights, const RayCaster& tracer,
                 int maxSegments)
        : lights_(lights),
          groups_(groups),
          seen_(seen),
          spectra_(spectra),
          m_(wavelengths),
          exactWeights_(exactWeights),
          tracer_(tracer),
          blocked_(std::size_t(maxSegments)),
          chosen_(blocked_.size()),
          kernel_(blocked_.size()),
          factor_(lights.size()),
          probability_(lights.size()),
          cdf_(groups.groups.size()),
          picks_(lights.size()),
          tally_(lights.size()),
          spectrumWeight_(spectra.size()) {
        segments_.resize(blocked_.size());
    }

    // A new pixel: each light's points start its stratified stream again, and the approximate
    // weights are made anew.
    void beginPixel() {
        std::fill(picks_.begin(), picks_.end(), 0);
        weightsPatch_ = kNoPatch;
        total_ = 0;
    }

    // Adds H(x) (m values) for sample s of the pixel at point x (normal n) on `patch`: k
    // segments, strata permute(s k + q) of the pixel's `strata`. Returns the sample's shadow
    // marks (shadowMark).
    uint64_t addIrradiance(shared::vec3 x, shared::vec3 n, uint32_t patch, int s, int k, int strata,
                           uint32_t pixelSeed, uint32_t sampleSeed, std::span<double> irradiance) {
        // With approximate weights, the samples of one pixel on one patch share the
        // distribution of the first of them (a fraction of a pixel away: still importance
        // sampling, each segment weighted by the exact factor over the shared weight), so a
        // supersampled edge pixel costs a few light loops, not one per sample.
        if (!lights_.empty() && (exactWeights_ || patch != weightsPatch_)) weigh(x, n, patch);
        const int drawn = total_ > 0 ? k : 0;
        if (drawn == 0) return 0;
        segments_.resize(std::size_t(drawn));
        for (int q = 0; q < drawn; ++q) {
            const uint32_t stratum =
                shared::permuteIndex(uint32_t(s * k + q), uint32_t(strata), pixelSeed);
            const double u = (stratum + double(shared::hashToUnitFloat(uint32_t(q), sampleSeed))) /
                strata * total_;
            const uint32_t l = draw(u);
            chosen_[std::size_t(q)] = l;
            const shared::vec3 e =
                pointInFront(lights_[l].geometry, x, n, shared::streamSeed(pixelSeed, uint32_t(l)),
                             picks_[l]++, strata);
            // Stop short of the light by kLightClearance of the distance, so a surface the
            // light lies on (a lamp face on its stand) does not block.
            const shared::vec3 end = e + (x - e) * kLightClearance;
            segments_.set(std::size_t(q), x.x, x.y, x.z, end.x, end.y, end.z);
            kernel_[std::size_t(q)] = pointKernel(x, n, lights_[l].geometry.normal, e);
        }
        tracer_.occluded(segments_, std::span<uint8_t>(blocked_.data(), std::size_t(drawn)));
        uint64_t mark = 0;
        touched_.clear();
        for (int q = 0; q < drawn; ++q) {
            const uint32_t l = chosen_[std::size_t(q)];
            const bool open = !blocked_[std::size_t(q)];
            LightTally& t = tally_[l];
            if (t.segments++ == 0) touched_.push_back(l);
            t.kernel += kernel_[std::size_t(q)];
            t.openKernel += open ? kernel_[std::size_t(q)] : 0.0;
            t.open += open ? 1 : 0;
            mark |= shadowMark(l, open);
        }
        if (exactWeights_)
            addExact(irradiance);
        else
            addImportanceSampled(x, n, k, irradiance);
        for (const uint32_t l : touched_)
            tally_[l] = {};
        return mark;
    }

private:
    // V_l: the kernel-weighted open fraction sum G open / sum G of the segments drawn to l (the
    // points are uniform in area, V weighs them by G: a ratio estimator, consistent, exact when
    // all are open or all blocked).
    static double openFraction(const LightTally& t) {
        return t.kernel > 0 ? t.openKernel / t.kernel : double(t.open) / std::max(1, t.segments);
    }

    // The light at u in [0, total): its group by the CDF, then (the group's share of u, so
    // the strata carry over) a light by area; sets its probability.
    uint32_t draw(double u) {
        const std::size_t g = std::min<std::size_t>(
            std::size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin()),
            cdf_.size() - 1);
        const LightGroup& group = groups_.groups[g];
        const double low = g > 0 ? cdf_[g - 1] : 0.0, weight = cdf_[g] - low;
        uint32_t l = group.first;
        double share = 1;
        if (group.count > 1) {
            const auto begin = groups_.areaCdf.begin() + group.first;
            const float v = float((u - low) / weight);
            l = std::min(group.first + group.count - 1,
                         uint32_t(std::upper_bound(begin, begin + group.count, v) -
                                  groups_.areaCdf.begin()));
            share = groups_.areaCdf[l] - (l > group.first ? groups_.areaCdf[l - 1] : 0.0f);
        }
        probability_[l] = weight / total_ * share;
        return l;
    }

    // The distribution the segments are drawn from: each group's factor (a light's exact one,
    // in SIMD lanes, or the stand-in) times its power, and its CDF.
    void weigh(shared::vec3 x, shared::vec3 n, uint32_t patch) {
        if (exactWeights_) {
            // The lights the patch can see, in SIMD lanes; the others' factor is exactly 0.
            receiver_.normal = n;
            const std::span<const uint32_t> seen = seen_.of(patch);
            batch_.points.clear();
            for (const uint32_t l : seen)
                batch_.points.push_back({x, &receiver_, &lights_[l].geometry});
            values_.resize(seen.size());
            pointToTriangleFactors(batch_.points, values_.data());
            std::fill(factor_.begin(), factor_.end(), 0.0f);
            for (std::size_t k = 0; k < seen.size(); ++k)
                factor_[seen[k]] = values_[k];
        }
        total_ = 0;
        for (std::size_t g = 0; g < cdf_.size(); ++g) {
            const LightGroup& group = groups_.groups[g];
            const Light& light = lights_[group.first];
            // Exact weights: the groups are single lights.
            const float factor = exactWeights_ ? factor_[group.first]
                : group.count == 1             ? approximateFactor(light.geometry, x, n)
                                               : groupFactor(group, light.geometry.normal, x, n);
            total_ += factor > 0 ? double(factor) * light.power : 0.0;
            cdf_[g] = total_;
        }
        weightsPatch_ = patch;
    }

    // Every light's F_l is known: H = sum_l E_l F_l V_l, a light that drew no segment taking the
    // pooled open fraction of those that did. Exact wherever every segment is open (or every
    // one blocked), whatever the lights' spectra. Summed per distinct spectrum.
    void addExact(std::span<double> irradiance) {
        LightTally pooled;
        for (const uint32_t l : touched_) {
            pooled.segments += tally_[l].segments;
            pooled.open += tally_[l].open;
        }
        const double otherwise = openFraction(pooled);
        std::fill(spectrumWeight_.begin(), spectrumWeight_.end(), 0.0);
        for (std::size_t l = 0; l < lights_.size(); ++l) {
            if (!(factor_[l] > 0)) continue;
            const double v = tally_[l].segments > 0 ? openFraction(tally_[l]) : otherwise;
            spectrumWeight_[lights_[l].spectrum] += double(factor_[l]) * v;
        }
        for (std::size_t e = 0; e < spectra_.size(); ++e) {
            if (!(spectrumWeight_[e] > 0)) continue;
            for (std::size_t w = 0; w < m_; ++w)
                irradiance[w] += spectra_[e][w] * spectrumWeight_[e];
        }
    }

    // Importance sampling over the lights: the n_l segments drawn to l estimate E_l F_l / p_l
    // each (draw's p_l: its group's weight over the total, times its share of the group's
    // area), n_l E_l F_l / (p_l k) in all, times V_l.
    void addImportanceSampled(shared::vec3 x, shared::vec3 n, int k, std::span<double> irradiance) {
        for (const uint32_t l : touched_) {
            const Light& light = lights_[l];
            const double factor = shared::pointToTriangleFactor(x, n, light.geometry);
            const double scale =
                factor * tally_[l].segments * openFraction(tally_[l]) / (probability_[l] * k);
            if (!(scale > 0)) continue;
            for (std::size_t w = 0; w < m_; ++w)
                irradiance[w] += light.emission[w] * scale;
        }
    }

    const std::vector<Light>& lights_;
    const LightGroups& groups_;
    const PatchLights& seen_;  // per patch, the lights it can see (exact weights only)
    const std::vector<const double*>& spectra_;  // the emission of each Light::spectrum
    std::size_t m_;
    bool exactWeights_;
    const RayCaster& tracer_;
    SegmentArrays segments_;
    std::vector<uint8_t> blocked_;
    std::vector<uint32_t> chosen_;  // per segment: its light
    std::vector<float> kernel_;  // per segment: pointKernel
    std::vector<float> factor_;  // per light: its exact factor (exact weights)
    std::vector<double> probability_;  // per light: its p_l in the draw (draw)
    std::vector<float> values_;  // per seen light: its exact factor from the batch
    std::vector<double> cdf_;  // per group
    std::vector<int> picks_;  // per light: points taken from its stream in this pixel
    std::vector<LightTally> tally_;
    std::vector<uint32_t> touched_;  // the lights this sample drew
    std::vector<double> spectrumWeight_;
    shared::PatchGeometry receiver_{};  // the batch's receiver: only its normal is read
    FarFieldScratch batch_;  // the seen lights as points of one factor batch (hybrid_far_field.h)
    uint32_t weightsPatch_ = kNoPatch;  // the patch cdf_ was made for
    double total_ = 0;
};

// How many times the segments of the other pixels a penumbra pixel takes (final_gather.h): 16
// where each light's exact factor weighs the draw (open segments then estimate exactly), 4 where
// the cheap stand-in does (each open segment carries its own ratio, so every pixel needs some).
constexpr int kPenumbraFactorExact = 16;
constexpr int kPenumbraFactorApproximate = 4;
// With the stand-in, a penumbra pixel takes this many times --gather-rays: the segments spread
// over many lights (over kExactLightLimit), each light's visibility estimated from its own few.
constexpr int kApproximateRayScale = 4;

// Per pixel, 1 where the marks of its 8 neighbours (not the pixel's own) hold both an open and a
// blocked segment to one light: a penumbra, or a shadow's edge, passes next to it.
std::vector<uint8_t> penumbraNeighbours(const std::vector<uint64_t>& marks, int width, int height) {
    std::vector<uint8_t> selected(marks.size(), 0);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            uint64_t around = 0;
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if ((dx != 0 || dy != 0) && nx >= 0 && ny >= 0 && nx < width && ny < height)
                        around |= marks[std::size_t(ny) * width + nx];
                }
            }
            selected[std::size_t(y) * width + x] =
                (around & (around >> 1) & 0x5555555555555555ull) != 0;
        }
    }
    return selected;
}

// The punctual lights' direct irradiance P(x) per sample: each light's factor
// (punctualPointFactor) behind one shadow segment from x, times its spectrum.
class PunctualSampler {
public:
    PunctualSampler(const std::vector<PunctualLight>& lights,
                    const std::vector<std::vector<double>>& spectra, double far,
                    const RayCaster& tracer)
        : lights_(lights), spectra_(spectra), far_(far), tracer_(tracer) {
        factor_.reserve(lights.size());
        index_.reserve(lights.size());
        blocked_.resize(lights.size());
    }

    void addIrradiance(const Vec3d& x, const Vec3d& n, std::span<double> irradiance) {
        factor_.clear();
        index_.clear();
        segments_.resize(lights_.size());
        for (std::size_t l = 0; l < lights_.size(); ++l) {
            Vec3d end;
            const double g = punctualPointFactor(lights_[l], x, n, far_, end);
            if (!(g > 0)) continue;
            segments_.set(factor_.size(), float(x.x), float(x.y), float(x.z), float(end.x),
                          float(end.y), float(end.z));
            factor_.push_back(g);
            index_.push_back(l);
        }
        if (factor_.empty()) return;
        segments_.resize(factor_.size());
        tracer_.occluded(segments_, std::span<uint8_t>(blocked_.data(), factor_.size()));
        for (std::size_t q = 0; q < factor_.size(); ++q) {
            if (blocked_[q]) continue;
            const std::vector<double>& spectrum = spectra_[index_[q]];
            for (std::size_t k = 0; k < irradiance.size(); ++k)
                irradiance[k] += factor_[q] * spectrum[k];
        }
    }

private:
    const std::vector<PunctualLight>& lights_;
    const std::vector<std::vector<double>>& spectra_;  // punctualLightSpectra
    double far_;
    const RayCaster& tracer_;
    SegmentArrays segments_;
    std::vector<double> factor_;
    std::vector<std::size_t> index_;
    std::vector<uint8_t> blocked_;
};

}  // namespace

std::vector<double> ownEmission(const RadiositySystem& system) {
    std::vector<double> own = system.emission;
    for (std::size_t i = 0; i < system.punctualEmission.size(); ++i)
        own[i] -= system.punctualEmission[i];
    return own;
}

std::vector<double> radiosityWithoutDirectLight(const RadiositySystem& system,
                                                const Transport& transport,
                                                std::span<const double> radiosity,
                                                std::span<const uint8_t> patches) {
    const std::size_t n = system.patchCount, m = system.wavelengthCount;
    DAISY_CHECK(radiosity.size() == n * m && transport.patchCount() == n);
    DAISY_CHECK(patches.empty() || patches.size() == n);
    const std::vector<double> own = ownEmission(system);
    std::vector<uint8_t> emitter(n), receiver(n);
    for (uint32_t j = 0; j < n; ++j) {
        emitter[j] = emits(own, m, j);
        receiver[j] = !system.operators[system.patchOperator[j]].isZero &&
            (patches.empty() || patches[j] != 0);
    }
    std::vector<double> direct(n * m, 0.0);
    transport.gatherFrom(emitter, receiver, own, m, direct);
    std::vector<double> out(radiosity.begin(), radiosity.end());
    std::vector<double> reflected(m);
    for (uint32_t i = 0; i < n; ++i) {
        if (!receiver[i]) continue;
        applyOperator(system.operators[system.patchOperator[i]], direct.data() + i * m,
                      reflected.data());
        for (std::size_t o = 0; o < m; ++o)
            out[i * m + o] -= reflected[o];
        if (!system.punctualEmission.empty()) {
            for (std::size_t o = 0; o < m; ++o)
                out[i * m + o] -= system.punctualEmission[i * m + o];
        }
    }
    return out;
}

Expected<std::vector<double>> patchDirectIrradiance(const Scene& scene, const PatchMesh& patches,
                                                    const RadiositySystem& system,
                                                    const DirectLightSettings& direct,
                                                    const CancelToken* cancel) {
    const std::size_t n = patches.patchCount(), m = system.wavelengthCount;
    std::vector<double> irradiance(n * m, 0.0);
    const std::vector<double> own = ownEmission(system);  // the lights point into it
    const std::vector<Light> lights = lightsOf(scene, patches, system, own);
    if (lights.empty()) return irradiance;
    auto caster = makeRayCaster(patches, {.packetMode = PacketMode::Packet16, .robust = true});
    if (!caster) return withContext(caster.error(), "direct light");
    const bool exactWeights = lights.size() <= kExactLightLimit;
    const PatchLights seen = exactWeights ? lightsSeenByPatches(patches, lights) : PatchLights{};
    const LightGroups groups = lightGroups(lights, !exactWeights);
    std::vector<const double*> spectra;
    for (const Light& light : lights) {
        if (light.spectrum >= spectra.size()) spectra.resize(light.spectrum + 1, nullptr);
        spectra[light.spectrum] = light.emission;
    }
    const int k = std::max(1, direct.shadowRays);
    const uint32_t seed = shared::pcgHash(direct.seed ^ 0x68e31da4u);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, uint32_t(n), 64), [&](const auto& range) {
        LightSampler sampler(lights, groups, seen, spectra, m, exactWeights, **caster, k);
        for (uint32_t p = range.begin(); p != range.end(); ++p) {
            if (isCancelled(cancel)) return;
            if (system.operators[system.patchOperator[p]].isZero) continue;
            const uint32_t patchSeed = shared::pcgHash(seed ^ shared::pcgHash(p));
            sampler.beginPixel();
            sampler.addIrradiance(toVec3(patches.centroids[p]), toVec3(patches.normals[p]), p, 0, k,
                                  k, patchSeed, shared::pcgHash(patchSeed ^ 0x9e3779b9u),
                                  std::span<double>(irradiance.data() + std::size_t(p) * m, m));
        }
    });
    return irradiance;
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
    auto caster = makeRayCaster(patches, {.packetMode = PacketMode::Packet16, .robust = true});
    if (!caster) return withContext(caster.error(), "final gather");
    const RayCaster& tracer = **caster;
    const std::vector<double> own = ownEmission(system);
    const std::vector<Light> lights = lightsOf(scene, patches, system, own);

    const std::size_t m = set.size();
    const int channels = int(spectral ? m : 0) + 4;
    const int xyzChannel = spectral ? int(m) : 0;
    Image image(settings.width, settings.height, channels);
    const bool gatherNear = nearField != nullptr && !nearField->empty();
    if (lights.empty() && scene.lights.empty() && !gatherNear) return image;
    auto punctualSpectra = punctualLightSpectra(scene.lights, set);
    if (!punctualSpectra) return withContext(punctualSpectra.error(), "final gather");
    const double far = leavingLength(patches);
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
    // Few lights: the exact factor of each, per sample. Many (over kExactLightLimit after the
    // faces are merged): a cheap approximation picks the lights and only the picked ones get
    // the exact factor.
    const bool exactWeights = lights.size() <= kExactLightLimit;
    const PatchLights seen = exactWeights ? lightsSeenByPatches(patches, lights) : PatchLights{};
    const LightGroups groups = lightGroups(lights, !exactWeights);
    std::vector<const double*> spectra;  // the emission of each Light::spectrum
    for (const Light& light : lights) {
        if (light.spectrum >= spectra.size()) spectra.resize(light.spectrum + 1, nullptr);
        spectra[light.spectrum] = light.emission;
    }
    const int penumbraFactor = exactWeights ? kPenumbraFactorExact : kPenumbraFactorApproximate;
    // --gather-rays (kApproximateRayScale times it with the stand-in) is per penumbra pixel;
    // the others take 1 / penumbraFactor of it (at least one), shared out over the pixel's
    // samples, at least one each; each sample draws its segments over all lights.
    const int penumbraRays =
        exactWeights ? direct.shadowRays : kApproximateRayScale * direct.shadowRays;
    const auto raysPerSample = [&](int samples) {
        const int base = std::max(1, penumbraRays / penumbraFactor);
        return std::max(1, (base + samples - 1) / samples);
    };
    const int maxK = raysPerSample(minSide * minSide);
    const uint32_t imageSeed = shared::pcgHash(direct.seed ^ 0x2545f491u);

    // Pass 1 renders every pixel with k segments a sample and marks, per light, whether its
    // segments were open or blocked. Pass 2 renders again, with (penumbraFactor - 1) k segments
    // a sample and an independent seed, the pixels whose 8 neighbours' marks hold both for one
    // light, and averages the two passes by their segment counts. A pixel's own marks never
    // select it, so its pass-1 value is independent of being selected: unbiased.
    std::vector<uint64_t> marks(std::size_t(settings.width) * settings.height, 0);
    std::vector<uint8_t> selected;
    struct Pass {
        int rayFactor;  // segments a sample, in units of raysPerSample
        uint32_t seed;
    };
    const auto renderRows = [&](const tbb::blocked_range<int>& rows, const Pass& pass) {
        const auto wanted = [&](int x, int y) {
            return selected.empty() || selected[std::size_t(y) * settings.width + x] != 0;
        };
        std::vector<Ray> rays(rowSamples);
        std::vector<SurfaceHit> hits(rowSamples);
        LightSampler sampler(lights, groups, seen, spectra, m, exactWeights, tracer,
                             maxK * pass.rayFactor);
        PunctualSampler punctual(scene.lights, *punctualSpectra, far, tracer);
        std::vector<double> irradiance(m), reflected(m), sum(static_cast<std::size_t>(channels));
        std::vector<double> sampleValues(std::size_t(xyzChannel) + 3);
        for (int y = rows.begin(); y != rows.end(); ++y) {
            std::size_t r = 0;
            for (int x = 0; x < settings.width; ++x) {
                if (!wanted(x, y)) continue;
                const int side = pixelSide(settings, x, y);
                for (int s = 0; s < side * side; ++s) {
                    const auto [ox, oy] = sampleOffset(s, side);
                    rays[r++] = primaryRay(camera, settings.width, settings.height, x + ox, y + oy);
                }
            }
            const std::size_t rowCount = r;
            if (rowCount == 0) continue;
            tracer.closestSurfaceHits(std::span<const Ray>(rays.data(), rowCount),
                                      std::span<SurfaceHit>(hits.data(), rowCount));
            if (shader != nullptr) {
                for (std::size_t i = 0; i < rowCount; ++i) {
                    if (hits[i].patch != kNoPatch) shader->resolve(rays[i], hits[i]);
                }
            }
            r = 0;
            for (int x = 0; x < settings.width; ++x) {
                if (!wanted(x, y)) continue;
                const int side = pixelSide(settings, x, y);
                const int samples = side * side;
                const int k = raysPerSample(samples) * pass.rayFactor;
                std::fill(sum.begin(), sum.end(), 0.0);
                uint64_t mark = 0;
                // The pixel's samples share one stratification of the light draw: pick q of
                // sample s takes stratum permute(s k + q) of samples x k (a per-pixel random
                // permutation, so each pick is marginally uniform: unbiased), and a light's
                // points continue one stratified stream across the pixel.
                const uint32_t pixelSeed = shared::pcgHash(
                    pass.seed ^
                    shared::pcgHash(uint32_t(y) * uint32_t(settings.width) + uint32_t(x)));
                sampler.beginPixel();
                const int strata = samples * k;
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
                    const uint32_t sampleSeed = shared::pcgHash(
                        pass.seed ^
                        shared::pcgHash((uint32_t(y) * uint32_t(settings.width) + uint32_t(x)) *
                                            uint32_t(samples) +
                                        uint32_t(s)));
                    std::fill(irradiance.begin(), irradiance.end(), 0.0);
                    const double covered =
                        gatherNear ? nearField->addIrradiance(p, hit.u, hit.v, irradiance) : 0.0;
                    mark |= sampler.addIrradiance(xf, nf, p, s, k, strata, pixelSeed, sampleSeed,
                                                  irradiance);
                    punctual.addIrradiance(px, n, irradiance);
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
                if (selected.empty()) {
                    for (int ch = 0; ch < channels; ++ch)
                        out[ch] = static_cast<float>(sum[std::size_t(ch)] / samples);
                    marks[std::size_t(y) * settings.width + x] = mark;
                } else {
                    // Weighted by segments: 1 share from pass 1, rayFactor shares from this.
                    const double w = double(pass.rayFactor) / (pass.rayFactor + 1);
                    for (int ch = 0; ch < channels; ++ch)
                        out[ch] = static_cast<float>((1 - w) * out[ch] +
                                                     w * sum[std::size_t(ch)] / samples);
                }
            }
        }
    };
    forEachImageRow(settings.height, settings.threads, [&](const tbb::blocked_range<int>& rows) {
        renderRows(rows, {1, imageSeed});
    });
    selected = penumbraNeighbours(marks, settings.width, settings.height);
    if (std::find(selected.begin(), selected.end(), 1) != selected.end()) {
        const Pass refine{penumbraFactor - 1, shared::pcgHash(imageSeed ^ 0x9e3779b9u)};
        forEachImageRow(settings.height, settings.threads,
                        [&](const tbb::blocked_range<int>& rows) { renderRows(rows, refine); });
    }
    return image;
}

}  // namespace daisy
