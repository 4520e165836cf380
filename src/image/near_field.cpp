#include "image/near_field.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "core/check.h"
#include "geometry/shared_vec.h"
#include "radiosity/hybrid_far_field.h"
#include "radiosity/patch_exposure.h"
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
constexpr std::size_t kPoints = kNodes + kPatchQuadraturePoints;  // nodes, then centroids
constexpr uint32_t kNoProbes = 0xffffffffu;  // a candidate not checked at the centroids
constexpr float kNodeInset = 1e-3f;  // share of the way to the centroid a node is moved
// The same for a sample gathered exactly: off an edge it may lie on, where a neighbour across
// the crease has its limit, and not much further (the factor changes fast near a neighbour).
constexpr float kSampleInset = 1e-4f;

// A patch's near field is gathered exactly at every sample (not interpolated on the lattice)
// when, for some neighbour j, the lattice's interpolant of w F(x -> j) is off by more than this
// at one of the 16 children's centroids, or j stands on the patch (standsOn): such a neighbour
// lights a strip narrower than the lattice's spacing (a poster panel's 2 cm side on a wall,
// docs/rendering.md). Every neighbour of the patch then, so errors of the interpolant that
// cancel between neighbours (a node on the line where one wall patch meets the next) are not
// left half in place.
constexpr double kLatticeTolerance = 0.1;
// On such a patch the 16-point rule's unoccluded mean, which the visibility F_ij / mean divides
// by, can be as far off as the lattice: where it is (its interpolation error over a quarter of
// the mean) and it would make the pair look occluded, the mean is taken from the hybrid kernel
// of the view factors instead.
constexpr double kRuleTolerance = 0.25;
// A visibility within 5% of 1 is the rule's error, and 1.
constexpr double kOpen = 0.95;

constexpr int nodeIndex(int a, int b) {
    return 5 * a - a * (a - 1) / 2 + b;
}

// Mean over the exposed children (bit q of `mask`) of the linear interpolant of the node values
// values[k * stride]: each child's mean is its three nodes' mean. 0 without exposed children.
template <typename T>
double exposedMean(const T* values, std::size_t stride, uint16_t mask) {
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

// Largest |f(centroid) - interpolant(centroid)| over the exposed children (bit q of `mask`) of
// one neighbour's values f at the nodes (f[0..14]) and the children's centroids (f[15..30]):
// the interpolant's value at a child's centroid is its three nodes' mean.
double latticeError(const double* f, uint16_t mask) {
    double worst = 0;
    int q = 0;
    const auto node = [&](int a, int b) { return f[nodeIndex(a, b)]; };
    const auto check = [&](double interpolated) {
        if (mask & (1u << q)) worst = std::max(worst, std::abs(f[kNodes + q] - interpolated));
        ++q;
    };
    for (int a = 0; a < kDivisions; ++a) {
        for (int b = 0; a + b < kDivisions; ++b) {
            check((node(a, b) + node(a + 1, b) + node(a, b + 1)) / 3);
            if (a + b < kDivisions - 1)
                check((node(a + 1, b) + node(a, b + 1) + node(a + 1, b + 1)) / 3);
        }
    }
    return worst;
}

// The unoccluded factor from the exposed part of patch i (its children with a bit in `mask`) to
// j, by the hybrid kernel of the view factors (shared/formfactor.h): the whole patch when all
// is exposed, else the mean over the exposed children.
double exposedUnoccludedFactor(const shared::PatchGeometry& i, const shared::PatchGeometry& j,
                               uint16_t mask) {
    constexpr int kLevel = 2;  // 16 cells before the kernel's own refinement
    if (mask == 0xffff) return shared::pairFactorUnoccluded(DAISY_METHOD_HYBRID, kLevel, i, j);
    const auto corner = [&](int a, int b) {
        const float u = float(a) / kDivisions, v = float(b) / kDivisions;
        return i.a * (1 - u - v) + i.b * u + i.c * v;
    };
    double sum = 0;
    int q = 0, count = 0;
    const auto child = [&](shared::vec3 p0, shared::vec3 p1, shared::vec3 p2) {
        if (mask & (1u << q)) {
            shared::PatchGeometry g = shared::makePatchGeometry(p0, p1, p2);
            g.normal = i.normal;  // every other child winds the other way
            g.area = i.area / kPatchQuadraturePoints;
            sum += shared::pairFactorUnoccluded(DAISY_METHOD_HYBRID, 0, g, j);
            ++count;
        }
        ++q;
    };
    for (int a = 0; a < kDivisions; ++a) {
        for (int b = 0; a + b < kDivisions; ++b) {
            child(corner(a, b), corner(a + 1, b), corner(a, b + 1));
            if (a + b < kDivisions - 1)
                child(corner(a + 1, b), corner(a, b + 1), corner(a + 1, b + 1));
        }
    }
    return count > 0 ? sum / count : 0.0;
}

// True when an edge of patch j lies in patch i's plane and runs through i's interior (a panel or
// a block standing on i): j's factor then peaks along a line inside i, narrower than the
// lattice's spacing when j is small, and the 16-point check can miss the peak between its points.
bool standsOn(const PatchMesh& patches, std::size_t i, std::size_t j) {
    const auto& pi = patches.patches[i];
    const Vec3d a = patches.positions[pi[0]], e1 = patches.positions[pi[1]] - a,
                e2 = patches.positions[pi[2]] - a;
    const Vec3d n = patches.normals[i];
    const double size = std::sqrt(std::max({dot(e1, e1), dot(e2, e2), dot(e2 - e1, e2 - e1)}));
    const double onPlane = 1e-3 * size, margin = 1e-3;
    const double d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2);
    const double denominator = d00 * d11 - d01 * d01;
    if (!(denominator > 0)) return false;
    const auto barycentrics = [&](const Vec3d& p) {
        const Vec3d d = p - a;
        const double b = (d11 * dot(d, e1) - d01 * dot(d, e2)) / denominator;
        const double c = (d00 * dot(d, e2) - d01 * dot(d, e1)) / denominator;
        return std::array<double, 3>{1 - b - c, b, c};
    };
    const auto& pj = patches.patches[j];
    for (int k = 0; k < 3; ++k) {
        const Vec3d p = patches.positions[pj[std::size_t(k)]],
                    q = patches.positions[pj[std::size_t((k + 1) % 3)]];
        if (std::abs(dot(n, p - a)) > onPlane || std::abs(dot(n, q - a)) > onPlane) continue;
        // The part of the segment p q at least `margin` inside every edge of i.
        const auto lp = barycentrics(p), lq = barycentrics(q);
        double lo = 0, hi = 1;
        for (int c = 0; c < 3 && lo < hi; ++c) {
            const double slope = lq[std::size_t(c)] - lp[std::size_t(c)];
            const double start = lp[std::size_t(c)] - margin;
            if (slope == 0) {
                if (start < 0) hi = lo;
            } else if (slope > 0) {
                lo = std::max(lo, -start / slope);
            } else {
                hi = std::min(hi, -start / slope);
            }
        }
        if (lo < hi) return true;
    }
    return false;
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
                           const Transport& transport, std::span<const double> radiosity,
                           const PatchExposure& exposure, const NearFieldSettings& settings,
                           std::span<const uint8_t> receivers) {
    const std::size_t n = patches.patchCount(), m = system.wavelengthCount;
    DAISY_CHECK(system.patchCount == n && transport.patchCount() == n &&
                radiosity.size() == n * m && exposure.fraction.size() == n);
    DAISY_CHECK(receivers.empty() || receivers.size() == n);
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
    std::vector<float> extents(n);  // the largest corner distance from the centroid
    std::vector<double> reflected(n * m);
    for (std::size_t p = 0; p < n; ++p) {
        const auto& c = patches.patches[p];
        geometry[p] = shared::makePatchGeometry(toVec3(patches.positions[c[0]]),
                                                toVec3(patches.positions[c[1]]),
                                                toVec3(patches.positions[c[2]]));
        geometry[p].normal = toVec3(patches.normals[p]);  // the double-precision normal, area
        geometry[p].area = float(patches.areas[p]);
        centroids[p] = toVec3(patches.centroids[p]);
        const shared::PatchGeometry& g = geometry[p];
        extents[p] = std::max(
            {length(g.a - centroids[p]), length(g.b - centroids[p]), length(g.c - centroids[p])});
        // The exposed part's reflected radiosity (patch_exposure.h); 0 for a buried patch.
        const double phi = field.exposed_[p];
        for (std::size_t k = 0; k < m; ++k)
            reflected[p * m + k] =
                phi > 0 ? (radiosity[p * m + k] - system.emissionRow(uint32_t(p))[k]) / phi : 0.0;
    }

    // Per receiving patch: its near candidates (j with F_ij > 0 whose centroid can come
    // within R of a point of i), nearest first, each one's visibility and share of the nodes'
    // Near and Omega (or, gathered exactly, of the per-sample list), and their means over i's
    // exposed children.
    const float reach = float(field.radius_);
    const std::size_t stride = m + 1;
    std::vector<std::vector<float>> values(n);
    std::vector<std::size_t> pairs(n, 0);
    std::vector<std::vector<ExactNeighbour>> exact(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 16), [&](const auto& range) {
        std::vector<TransportEntry> entries;  // row i of the transport
        std::vector<std::pair<float, uint32_t>> candidates;
        std::array<shared::vec3, kPoints> x{};  // the nodes, then the children's centroids
        FarFieldScratch batch;  // the candidates' factors at x, in SIMD lanes
        std::vector<float> factors;
        std::vector<double> weighted;  // per candidate, w F at x
        std::vector<uint32_t> probes;  // per candidate, its centroids' first factor, if any
        std::vector<double> sums(kNodes * stride);
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const double phi = field.exposed_[i];
            if (system.operators[system.patchOperator[i]].isZero || phi <= 0) continue;
            if (!receivers.empty() && receivers[i] == 0) continue;
            transport.row(uint32_t(i), entries);
            if (!(reach > 0) || settings.maxNeighbours <= 0) continue;
            const shared::PatchGeometry& gi = geometry[i];
            const shared::vec3 ci = centroids[i];
            const float extent = extents[i];
            candidates.clear();
            const float limit2 = (reach + extent) * (reach + extent);
            for (std::size_t e = 0; e < entries.size(); ++e) {
                const shared::vec3 d = centroids[entries[e].patch] - ci;
                const float d2 = dot(d, d);  // squared: sorts the same, no root per entry
                if (entries[e].factor > 0 && d2 < limit2) candidates.push_back({d2, uint32_t(e)});
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
            for (int q = 0; q < kPatchQuadraturePoints; ++q)
                x[std::size_t(kNodes + q)] = patchQuadraturePoint(gi, q);
            const uint16_t mask = exposure.exposedPoints[i];
            const int exposedChildren = std::popcount(mask);
            std::fill(sums.begin(), sums.end(), 0.0);
            // shared::pointToTriangleFactor(x_k, n_i, j) for every candidate j at the nodes, and
            // at the children's centroids for the candidates near enough for the lattice to
            // miss their light (its interpolant is off by about F h^2 / (8 d^2) at a distance d
            // from j, h the nodes' spacing, about half the extent: beyond d = extent, by F / 32
            // at most), in one batch (bit-identical, radiosity/hybrid_far_field.h).
            batch.points.clear();
            probes.assign(candidates.size(), kNoProbes);
            for (const auto& candidate : candidates) {
                for (int k = 0; k < kNodes; ++k)
                    batch.points.push_back(
                        {x[std::size_t(k)], &gi, &geometry[entries[candidate.second].patch]});
            }
            for (std::size_t c = 0; c < candidates.size(); ++c) {
                const uint32_t j = entries[candidates[c].second].patch;
                if (length(centroids[j] - ci) - extent - extents[j] > extent) continue;
                probes[c] = uint32_t(batch.points.size());
                for (std::size_t k = kNodes; k < kPoints; ++k)
                    batch.points.push_back({x[k], &gi, &geometry[j]});
            }
            factors.resize(batch.points.size());
            pointToTriangleFactors(batch.points, factors.data());
            // w(|x - c_j|) F(x -> j) at the points, per candidate; the patch is gathered exactly
            // per sample when the lattice cannot follow one of them (kLatticeTolerance).
            weighted.resize(candidates.size() * kPoints);
            bool exactPatch = false;
            for (std::size_t c = 0; c < candidates.size(); ++c) {
                const uint32_t j = entries[candidates[c].second].patch;
                double* f = weighted.data() + c * kPoints;
                for (std::size_t k = 0; k < kPoints; ++k) {
                    const bool node = k < std::size_t(kNodes);
                    if (!node && probes[c] == kNoProbes) break;
                    f[k] = field.windowWeight(length(x[k] - centroids[j])) *
                        (node ? factors[c * kNodes + k] : factors[probes[c] + k - kNodes]);
                }
                exactPatch = exactPatch ||
                    (probes[c] != kNoProbes &&
                     (latticeError(f, mask) > kLatticeTolerance || standsOn(patches, i, j)));
            }
            for (std::size_t c = 0; c < candidates.size(); ++c) {
                const uint32_t e = candidates[c].second;
                const uint32_t j = entries[e].patch;
                const double* f = weighted.data() + c * kPoints;
                // The unoccluded exposed mean and that of w F by the children's centroids (the
                // equal-area rule), by the lattice for far candidates, or by the hybrid kernel
                // where the rule is off (kRuleTolerance).
                double unoccluded = 0, windowed = 0;
                if (probes[c] == kNoProbes) {
                    unoccluded = exposedMean(factors.data() + c * kNodes, 1, mask);
                    windowed = exposedMean(f, 1, mask);
                } else {
                    for (int q = 0; q < kPatchQuadraturePoints; ++q) {
                        if (!((mask >> q) & 1u)) continue;
                        unoccluded += factors[probes[c] + std::size_t(q)];
                        windowed += f[kNodes + q];
                    }
                    unoccluded /= std::max(exposedChildren, 1);
                    windowed /= std::max(exposedChildren, 1);
                }
                if (exactPatch && probes[c] != kNoProbes &&
                    (!(unoccluded > 0) ||
                     (entries[e].factor / phi < kOpen * unoccluded &&
                      latticeError(f, mask) > kRuleTolerance * unoccluded))) {
                    const double rule = unoccluded;
                    unoccluded = exposedUnoccludedFactor(gi, geometry[j], mask);
                    windowed = rule > 0
                        ? windowed / rule * unoccluded
                        : field.windowWeight(length(ci - centroids[j])) * unoccluded;
                }
                if (!(unoccluded > 0)) continue;
                // F_ij of the exposed part over its unoccluded mean: the pair's visibility.
                double visibility = std::min(1.0, entries[e].factor / phi / unoccluded);
                if (visibility > kOpen) visibility = 1;
                ++pairs[i];
                if (exactPatch) {
                    exact[i].push_back({j, float(visibility)});
                    const double share = visibility * windowed;
                    for (std::size_t l = 0; l < m; ++l)
                        field.patchMeans_[i * m + l] += share * reflected[j * m + l];
                    field.coverage_[i] += share;
                    continue;
                }
                for (int k = 0; k < kNodes; ++k) {
                    const double w = visibility * f[k];
                    double* node = sums.data() + std::size_t(k) * stride;
                    for (std::size_t l = 0; l < m; ++l)
                        node[l] += w * reflected[j * m + l];
                    node[m] += w;
                }
            }
            if (pairs[i] == 0 || exactPatch) continue;
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
    field.firstExact_.assign(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        field.exact_.insert(field.exact_.end(), exact[i].begin(), exact[i].end());
        field.firstExact_[i + 1] = uint32_t(field.exact_.size());
    }
    if (!field.exact_.empty()) {
        field.geometry_ = std::move(geometry);
        field.centroids_ = std::move(centroids);
        field.reflected_ = std::move(reflected);
    }
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
    const bool punctual = !system.punctualEmission.empty();
    std::vector<double> indirect(m), mean(m), reradiated(m), own(m);
    for (std::size_t i = 0; i < n; ++i) {
        const MaterialOperator& op = system.operators[system.patchOperator[i]];
        const double phi = exposed_[i];
        if (op.isZero || phi <= 0) continue;
        const double* e = system.emissionRow(uint32_t(i));
        if (punctual) {
            for (std::size_t k = 0; k < m; ++k)
                own[k] = e[k] - system.punctualEmission[i * m + k];
            e = own.data();
        }
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
    if (empty()) return 0;
    double omega = 0;
    if (firstExact_[patch] != firstExact_[patch + 1]) {
        // Gathered exactly at the sample itself.
        const shared::PatchGeometry& gi = geometry_[patch];
        const float w1 = std::clamp(u, 0.0f, 1.0f), w2 = std::clamp(v, 0.0f, 1.0f - w1);
        shared::vec3 x = gi.a * (1 - w1 - w2) + gi.b * w1 + gi.c * w2;
        x = x + (centroids_[patch] - x) * kSampleInset;
        // The factors in SIMD lanes (radiosity/hybrid_far_field.h), per thread.
        thread_local FarFieldScratch batch;
        thread_local std::vector<float> factors;
        const uint32_t first = firstExact_[patch], count = firstExact_[patch + 1] - first;
        batch.points.resize(count);
        for (uint32_t e = 0; e < count; ++e)
            batch.points[e] = {x, &gi, &geometry_[exact_[first + e].patch]};
        factors.resize(count);
        pointToTriangleFactors(batch.points, factors.data());
        for (uint32_t e = 0; e < count; ++e) {
            const uint32_t j = exact_[first + e].patch;
            const double w =
                windowWeight(length(x - centroids_[j])) * exact_[first + e].visibility * factors[e];
            for (std::size_t k = 0; k < m; ++k)
                irradiance[k] += w * reflected_[j * m + k];
            omega += w;
        }
        return omega;
    }
    if (firstNode_[patch] == kNoNodes) return 0;
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
