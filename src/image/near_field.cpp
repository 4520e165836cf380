#include "image/near_field.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "core/check.h"
#include "pipeline/patch_exposure.h"
#include "radiosity/hybrid_far_field.h"
#include "shared/formfactor.h"

namespace daisy {

namespace {

// Least far share 1 - Omega_i the far radiosity is spread over (a patch deep in a crevice).
constexpr double kMinFarShare = 0.05;

// Least exposed share a partly buried patch's values are divided by: phi counts 16 points, so
// under 4 of them it is too coarse (the solution's own exposed share may be twice or half) for
// a division not to amplify; such slivers are corrected in part. Costs the Cornell box 0.006
// points (docs/performance.md).
constexpr float kMinExposedShare = 0.25f;

// The lattice: nodes (a, b), a + b <= 4, at barycentrics a / 4 on corner 1 and b / 4 on corner
// 2; its 16 children are patch_exposure.h's, in the same order.
constexpr int kDivisions = 4;
constexpr int kNodes = 15;
constexpr float kNodeInset = 1e-3f;  // share of the way to the centroid a node is moved

constexpr int nodeIndex(int a, int b) {
    return 5 * a - a * (a - 1) / 2 + b;
}

// Mean over the exposed children (bit q of `mask`) of the linear interpolant of the node values
// values[k * stride]: each child's mean is its three nodes' mean. 0 without exposed children.
double exposedMean(const double* values, std::size_t stride, uint16_t mask) {
    double sum = 0;
    int q = 0, count = 0;
    const auto node = [&](int a, int b) { return values[std::size_t(nodeIndex(a, b)) * stride]; };
    for (int a = 0; a < kDivisions; ++a) {
        for (int b = 0; a + b < kDivisions; ++b) {
            if (mask & (1u << q++)) {
                sum += (node(a, b) + node(a + 1, b) + node(a, b + 1)) / 3;
                ++count;
            }
            if (a + b < kDivisions - 1 && (mask & (1u << q++))) {
                sum += (node(a + 1, b) + node(a, b + 1) + node(a + 1, b + 1)) / 3;
                ++count;
            }
        }
    }
    return count > 0 ? sum / count : 0.0;
}

double exposedMean(const float* values, std::size_t stride, uint16_t mask) {
    double copy[kNodes];
    for (int k = 0; k < kNodes; ++k)
        copy[k] = values[std::size_t(k) * stride];
    return exposedMean(copy, 1, mask);
}

shared::vec3 toVec3(const Vec3d& v) {
    return {float(v.x), float(v.y), float(v.z)};
}

// The median over patches of the longest edge: the scene's patch size.
double medianPatchSize(const PatchMesh& patches) {
    std::vector<double> edges(patches.patchCount());
    for (std::size_t p = 0; p < edges.size(); ++p) {
        const auto& c = patches.patches[p];
        const Vec3d &a = patches.positions[c[0]], &b = patches.positions[c[1]],
                    &d = patches.positions[c[2]];
        edges[p] = std::sqrt(std::max({dot(b - a, b - a), dot(d - b, d - b), dot(a - d, a - d)}));
    }
    if (edges.empty()) return 0;
    std::nth_element(edges.begin(), edges.begin() + std::ptrdiff_t(edges.size() / 2), edges.end());
    return edges[edges.size() / 2];
}

}  // namespace

double NearField::windowWeight(double distance) const {
    const double t = 4 * distance / radius_ - 3;  // 0 at 3R / 4, 1 at R
    if (t <= 0) return 1;
    if (t >= 1) return 0;
    return 1 - t * t * (3 - 2 * t);
}

NearField NearField::build(const PatchMesh& patches, const RadiositySystem& system,
                           const SparseMatrix& formFactors, std::span<const double> radiosity,
                           const PatchExposure& exposure, const NearFieldSettings& settings) {
    const std::size_t n = patches.patchCount(), m = system.wavelengthCount;
    DAISY_CHECK(system.patchCount == n && formFactors.size == n && radiosity.size() == n * m &&
                exposure.fraction.size() == n);
    NearField field;
    field.wavelengthCount_ = m;
    field.radius_ = std::max(0.0, settings.radius * medianPatchSize(patches));
    // phi for the division, at least kMinExposedShare where any point is exposed.
    field.exposed_ = exposure.fraction;
    for (float& phi : field.exposed_)
        phi = phi > 0 ? std::max(phi, kMinExposedShare) : 0.0f;
    field.firstNode_.assign(n, kNoNodes);
    field.patchMeans_.assign(n * m, 0.0);
    field.coverage_.assign(n, 0.0);
    std::vector<shared::PatchGeometry> geometry(n);
    std::vector<shared::vec3> centroids(n);
    std::vector<double> reflected(n * m);
    for (std::size_t p = 0; p < n; ++p) {
        const auto& c = patches.patches[p];
        geometry[p] = shared::makePatchGeometry(toVec3(patches.positions[c[0]]),
                                                toVec3(patches.positions[c[1]]),
                                                toVec3(patches.positions[c[2]]));
        geometry[p].normal = toVec3(patches.normals[p]);  // the double-precision normal, area
        geometry[p].area = float(patches.areas[p]);
        centroids[p] = toVec3(patches.centroids[p]);
        // The exposed part's reflected radiosity (patch_exposure.h); 0 for a buried patch.
        const double phi = field.exposed_[p];
        for (std::size_t k = 0; k < m; ++k)
            reflected[p * m + k] =
                phi > 0 ? (radiosity[p * m + k] - system.emissionRow(uint32_t(p))[k]) / phi : 0.0;
    }

    // Per receiving patch: its near candidates (j with F_ij > 0 whose centroid can come
    // within R of a point of i), nearest first, each one's visibility and share of the nodes'
    // Near and Omega, and their means over i's exposed children.
    const float reach = float(field.radius_);
    const std::size_t stride = m + 1;
    std::vector<std::vector<float>> values(n);
    std::vector<std::size_t> pairs(n, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 16), [&](const auto& range) {
        std::vector<std::pair<float, uint32_t>> candidates;
        std::array<shared::vec3, kNodes> x{};
        FarFieldScratch batch;  // the candidates' node factors, in SIMD lanes
        std::vector<float> factors;
        std::vector<double> sums(kNodes * stride);
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const double phi = field.exposed_[i];
            if (system.operators[system.patchOperator[i]].isZero || phi <= 0) continue;
            const auto columns = formFactors.rowColumns(uint32_t(i));
            const auto fij = formFactors.rowValues(uint32_t(i));
            if (!(reach > 0) || settings.maxNeighbours <= 0) continue;
            const shared::PatchGeometry& gi = geometry[i];
            const shared::vec3 ci = centroids[i];
            const float extent =
                std::max({length(gi.a - ci), length(gi.b - ci), length(gi.c - ci)});
            candidates.clear();
            const float limit2 = (reach + extent) * (reach + extent);
            for (std::size_t e = 0; e < columns.size(); ++e) {
                const shared::vec3 d = centroids[columns[e]] - ci;
                const float d2 = dot(d, d);  // squared: sorts the same, no root per entry
                if (fij[e] > 0 && d2 < limit2) candidates.push_back({d2, uint32_t(e)});
            }
            if (candidates.empty()) continue;
            std::sort(candidates.begin(), candidates.end());
            if (candidates.size() > std::size_t(settings.maxNeighbours))
                candidates.resize(std::size_t(settings.maxNeighbours));
            for (int a = 0; a <= kDivisions; ++a) {
                for (int b = 0; a + b <= kDivisions; ++b) {
                    const float u = float(a) / kDivisions, v = float(b) / kDivisions;
                    const shared::vec3 node = gi.a * (1 - u - v) + gi.b * u + gi.c * v;
                    x[std::size_t(nodeIndex(a, b))] = node + (ci - node) * kNodeInset;
                }
            }
            const uint16_t mask = exposure.exposedPoints[i];
            std::fill(sums.begin(), sums.end(), 0.0);
            // shared::pointToTriangleFactor(x_k, n_i, j) for every candidate j and node k, in
            // one batch (bit-identical, radiosity/hybrid_far_field.h).
            batch.points.clear();
            for (const auto& candidate : candidates) {
                for (int k = 0; k < kNodes; ++k)
                    batch.points.push_back(
                        {x[std::size_t(k)], &gi, &geometry[columns[candidate.second]]});
            }
            factors.resize(batch.points.size());
            pointToTriangleFactors(batch, factors.data());
            for (std::size_t c = 0; c < candidates.size(); ++c) {
                const uint32_t e = candidates[c].second;
                const uint32_t j = columns[e];
                const float* factor = factors.data() + c * kNodes;
                const double unoccluded = exposedMean(factor, 1, mask);
                if (!(unoccluded > 0)) continue;
                // F_ij of the exposed part over its unoccluded mean: the pair's visibility;
                // within 5% of 1 it is the rule's error, and 1.
                double visibility = std::min(1.0, fij[e] / phi / unoccluded);
                if (visibility > 0.95) visibility = 1;
                for (int k = 0; k < kNodes; ++k) {
                    const double w = field.windowWeight(length(x[std::size_t(k)] - centroids[j])) *
                        visibility * factor[k];
                    double* node = sums.data() + std::size_t(k) * stride;
                    for (std::size_t l = 0; l < m; ++l)
                        node[l] += w * reflected[j * m + l];
                    node[m] += w;
                }
                ++pairs[i];
            }
            if (pairs[i] == 0) continue;
            for (std::size_t l = 0; l < m; ++l)
                field.patchMeans_[i * m + l] = exposedMean(sums.data() + l, stride, mask);
            field.coverage_[i] = exposedMean(sums.data() + m, stride, mask);
            values[i].assign(sums.begin(), sums.end());
        }
    });
    std::size_t total = 0;
    for (const auto& v : values)
        total += v.size();
    field.nodes_.reserve(total);
    for (std::size_t i = 0; i < n; ++i) {
        field.pairCount_ += pairs[i];
        if (values[i].empty()) continue;
        field.firstNode_[i] = uint32_t(field.nodes_.size() / stride);
        field.nodes_.insert(field.nodes_.end(), values[i].begin(), values[i].end());
        std::vector<float>().swap(values[i]);  // the copies go as the lattice fills
    }
    return field;
}

void NearField::toFarRadiosity(const RadiositySystem& system, std::span<double> b) const {
    const std::size_t m = wavelengthCount_, n = exposed_.size();
    DAISY_CHECK(b.size() == n * m);
    std::vector<double> indirect(m), mean(m), reradiated(m);
    for (std::size_t i = 0; i < n; ++i) {
        const MaterialOperator& op = system.operators[system.patchOperator[i]];
        const double phi = exposed_[i];
        if (op.isZero || phi <= 0) continue;
        const double* e = system.emissionRow(uint32_t(i));
        // (B_i - E_i) / phi_i - M_i N_i: the exposed part's far indirect light, spread over
        // 1 - Omega_i of its hemisphere.
        const double* near = patchMeans_.data() + i * m;
        for (std::size_t k = 0; k < m; ++k)
            mean[k] = -phi * near[k];
        applyOperator(op, mean.data(), reradiated.data());
        for (std::size_t o = 0; o < m; ++o)
            indirect[o] = (b[i * m + o] - e[o] + reradiated[o]) / phi;
        const double spread = 1 / std::max(1 - coverage_[i], kMinFarShare);
        for (std::size_t o = 0; o < m; ++o)
            b[i * m + o] = e[o] + indirect[o] * spread;
    }
}

void NearField::setSmoothImage(std::vector<float> corners, std::vector<float> emission,
                               int channels) {
    DAISY_CHECK(channels > 0 && corners.size() == exposed_.size() * 3 * std::size_t(channels) &&
                emission.size() == exposed_.size() * std::size_t(channels));
    corners_ = std::move(corners);
    emission_ = std::move(emission);
    channels_ = channels;
}

void NearField::removeCovered(const SurfaceHit& hit, double omega, std::span<double> values) const {
    DAISY_CHECK(values.size() <= std::size_t(channels_));
    if (omega == 0) return;
    const std::size_t stride = std::size_t(channels_);
    const float* v = corners_.data() + std::size_t(hit.patch) * 3 * stride;
    const float* e = emission_.data() + std::size_t(hit.patch) * stride;
    const double w1 = hit.u, w2 = hit.v, w0 = 1 - w1 - w2;  // as renderCornerValues
    for (std::size_t c = 0; c < values.size(); ++c)
        values[c] -= omega * (w0 * v[c] + w1 * v[stride + c] + w2 * v[2 * stride + c] - e[c]);
}

double NearField::addIrradiance(uint32_t patch, float u, float v,
                                std::span<double> irradiance) const {
    const std::size_t m = wavelengthCount_;
    DAISY_CHECK(irradiance.size() == m);
    if (nodes_.empty() || firstNode_[patch] == kNoNodes) return 0;
    // The lattice triangle holding (u, v) and its linear weights.
    const float s = std::clamp(u, 0.0f, 1.0f) * kDivisions,
                t = std::clamp(v, 0.0f, 1.0f) * kDivisions;
    const int a = std::min(int(s), kDivisions - 1);
    const int b = std::clamp(int(t), 0, kDivisions - 1 - a);
    const float fs = s - float(a), ft = t - float(b);
    int corner[3];
    float weight[3];
    if (fs + ft <= 1 || a + b == kDivisions - 1) {
        corner[0] = nodeIndex(a, b), corner[1] = nodeIndex(a + 1, b),
        corner[2] = nodeIndex(a, b + 1);
        weight[0] = 1 - fs - ft, weight[1] = fs, weight[2] = ft;
    } else {
        corner[0] = nodeIndex(a + 1, b + 1), corner[1] = nodeIndex(a, b + 1),
        corner[2] = nodeIndex(a + 1, b);
        weight[0] = fs + ft - 1, weight[1] = 1 - fs, weight[2] = 1 - ft;
    }
    const std::size_t stride = m + 1;
    const float* first = nodes_.data() + std::size_t(firstNode_[patch]) * stride;
    double omega = 0;
    for (int c = 0; c < 3; ++c) {
        const float* node = first + std::size_t(corner[c]) * stride;
        const double w = weight[c];
        for (std::size_t k = 0; k < m; ++k)
            irradiance[k] += w * node[k];
        omega += w * node[m];
    }
    return omega;
}

}  // namespace daisy
