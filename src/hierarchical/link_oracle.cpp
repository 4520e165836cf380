#include "hierarchical/link_oracle.h"

#include <algorithm>
#include <cmath>

#include "spectral/cie_tables.h"

namespace daisy {
namespace {

// CIE 1931 ybar at `nm`, linearly interpolated in the 1 nm table; 0 outside it.
double ybarAt(double nm) {
    const double x = nm - kCieCmfFirstNm;
    if (!(x >= 0) || x > kCieCmfCount - 1) return 0;
    const auto k = static_cast<std::size_t>(x);
    const double t = x - double(k);
    const double a = kCie1931Cmf[k][1];
    const double b = k + 1 < kCieCmfCount ? kCie1931Cmf[k + 1][1] : a;
    return a + (b - a) * t;
}

// sum_o M[o][k] weight_o w_o for every k: the weighted exitance per unit irradiance at k.
std::vector<double> weightedColumns(const MaterialOperator& op, const std::vector<double>& weight,
                                    const std::vector<double>& widths) {
    const std::size_t m = widths.size();
    std::vector<double> out(m, 0.0);
    for (std::size_t o = 0; o < m; ++o) {
        for (std::size_t k = 0; k <= o; ++k) {
            const double value =
                op.isDiagonal ? (k == o ? op.diagonal[o] : 0.0) : op.matrix.values[o * m + k];
            out[k] += value * weight[o] * widths[o];
        }
    }
    return out;
}

// Angles are compared with this margin (radians) so rounding never lets a cosine reach 0.
constexpr double kFacingMargin = 1e-6;

// facingNormals' question (below) answered from the box of the node's normals
// (HierarchyNode::normalLo, normalHi): a unit normal n and a unit w within sigma of u have
// n . w >= n . u - |w - u|, |w - u| is at most the chord 2 sin(sigma / 2), and n . u ranges
// over the box's corners.
int facingBox(const HierarchyNode& node, const Vec3d& u, double sinSpread) {
    double lo = 0, hi = 0;
    for (int k = 0; k < 3; ++k) {
        const double a = node.normalLo[k] * u[k], b = node.normalHi[k] * u[k];
        lo += std::min(a, b), hi += std::max(a, b);
    }
    const double chord = std::sqrt(std::max(0.0, 2 - 2 * std::sqrt(1 - sinSpread * sinSpread)));
    if (lo > chord + kFacingMargin) return 1;
    if (hi < -chord - kFacingMargin) return -1;
    return 0;
}

// Whether every normal of `node` faces every direction within angle sigma of the unit
// direction u (+1), none does (-1), or some do (0); sinSpread = sin sigma, sigma in
// [0, pi / 2]. Either of two bounds on the normals may settle it: their box (facingBox), tight
// where the cone is loose (the normals of a strip of a barrel vault lie on an arc across the
// barrel, while the cone round them reaches along it: by the cone alone a strip faced a point
// down the barrel only in part, and the vault's pairs went down to single patches, a ceiling
// patch of the 120,000-triangle interior linked to 654 single patches on average, to 33 with
// the box), or the cone. With theta the cone's half angle, alpha the angle of its axis to u and
// h = theta + sigma: every one when alpha + h < pi / 2 - margin, none when
// alpha - h > pi / 2 + margin. Both need h + margin < pi / 2, and then read
// cos alpha > sin(h + margin) and cos alpha < -sin(h + margin): compared in cosines, from the
// angle sums' sines and cosines, with no inverse trigonometric function (this runs for every
// node pair the refinement examines).
int facingNormals(const HierarchyNode& node, const Vec3d& u, double sinSpread) {
    if (const int byBox = facingBox(node, u, sinSpread); byBox != 0) return byBox;
    if (node.coneCos <= -1) return 0;
    static const double sinMargin = std::sin(kFacingMargin), cosMargin = std::cos(kFacingMargin);
    const double cosTheta = std::clamp(node.coneCos, -1.0, 1.0);
    const double sinTheta = std::sqrt(1 - cosTheta * cosTheta);
    const double cosSigma = std::sqrt(1 - sinSpread * sinSpread);
    const double cosH = cosTheta * cosSigma - sinTheta * sinSpread;
    const double sinH = sinTheta * cosSigma + cosTheta * sinSpread;
    const double cosLimit = cosH * cosMargin - sinH * sinMargin;  // cos(h + margin)
    const double sinLimit = sinH * cosMargin + cosH * sinMargin;  // sin(h + margin)
    if (!(cosLimit > 0 && sinLimit >= 0)) return 0;  // h + margin >= pi / 2
    const double cosAlpha = dot(node.coneAxis, u);
    if (cosAlpha > sinLimit) return 1;
    if (cosAlpha < -sinLimit) return -1;
    return 0;
}

// The range of n . x over the corners of node `s` (n a unit vector): exact from a planar node's
// slab when n is its axis (either way round), else from its bounding box.
std::pair<double, double> extentAlong(const HierarchyNode& s, const Vec3d& n) {
    const double along = dot(n, s.coneAxis);
    const double thickness = s.slabHi - s.slabLo;  // also bounds the tilt's effect
    if (s.isPlanar() && along >= 1 - 1e-9) return {s.slabLo - thickness, s.slabHi + thickness};
    if (s.isPlanar() && along <= -1 + 1e-9) return {-s.slabHi - thickness, -s.slabLo + thickness};
    const Vec3d mid = (s.boxLo + s.boxHi) * 0.5, half = (s.boxHi - s.boxLo) * 0.5;
    const double c = dot(n, mid);
    const double r = std::abs(n.x) * half.x + std::abs(n.y) * half.y + std::abs(n.z) * half.z;
    return {c - r, c + r};
}

// Whether R's patches face all of S (+1: S lies in front of every patch's plane, so every
// cosine on R's side is >= 0), none of it (-1), or some (0). A planar R (isPlanar) is decided
// by S's extent along its normal: in front of the slab's highest face, or behind its lowest
// (a thin slab's coplanar parts included: the cosines are all but 0 there, as for coplanar
// parts of a wall, or a wall and its own back faces; the matrix path treats coplanar clusters
// alike, radiosity/patch_clusters.h). Between the two, S faces some of R's faces (a thick slab:
// the undersides of shelves at several heights). Otherwise by R's normal cone against the
// directions to S's bounding sphere.
int facing(const HierarchyNode& r, const HierarchyNode& s) {
    if (r.isPlanar()) {
        const double tolerance = 1e-7 * (r.radius + s.radius);
        const auto [lo, hi] = extentAlong(s, r.coneAxis);
        if (hi <= r.slabLo + tolerance) return -1;  // behind every face, or coplanar: first
        if (lo >= r.slabHi - tolerance) return 1;
        return 0;
    }
    const Vec3d between = s.center - r.center;
    const double d = length(between);
    const double rho = r.radius + s.radius;
    if (!(d > rho)) return 0;
    return facingNormals(r, between / d, std::min(1.0, rho / d));
}

}  // namespace

LinkChoice splitChoice(const HierarchyNode& r, const HierarchyNode& s) {
    if (r.isLeaf() && s.isLeaf()) return LinkChoice::Near;
    return !r.isLeaf() && (s.isLeaf() || r.radius >= s.radius) ? LinkChoice::SplitReceiver
                                                               : LinkChoice::SplitSource;
}

LinkDecision chooseLink(const HierarchyNode& r, const HierarchyNode& s, const LinkWeights& weights,
                        double epsilon, double maxAperture) {
    LinkDecision decision;
    const bool carries = weights.sourceS * weights.yieldR + weights.sourceR * weights.yieldS > 0;
    const int rFaces = facing(r, s), sFaces = facing(s, r);
    if (!carries || rFaces < 0 || sFaces < 0) {
        decision.choice = LinkChoice::None;
        return decision;
    }
    const double d = length(s.center - r.center);
    const double rho = r.radius + s.radius;
    const bool apart = d > rho;
    if (apart) {
        const double gap = d - rho;
        const double coupling = std::min({r.area, s.area, r.area * s.area / (M_PI * gap * gap)});
        decision.power =
            coupling * (weights.sourceS * weights.yieldR + weights.sourceR * weights.yieldS);
    }
    // A pair whose whole exchange is within epsilon: a far link's estimate of it lies in
    // [0, kFarEstimateBound Phi] (hierarchical_links.h), so its error is within epsilon at
    // any aperture, and at any level: such a pair is never cut down to its leaves.
    const bool small = apart && kFarEstimateBound * decision.power <= epsilon;
    if (rFaces > 0 && sFaces > 0 && apart) {
        // Each side's share of the bound: only splitting a side reduces its share, and a leaf
        // cannot be split; its share is the patch's own resolution (the first-order term
        // cancels in the patch's mean and the second-order one is corrected: c in
        // hierarchical_links.h), so it is not charged unless both sides are leaves.
        const double errorR = decision.power * r.radius / d;
        const double errorS = decision.power * s.radius / d;
        const bool leaves = r.isLeaf() && s.isLeaf();
        decision.error =
            (leaves || !r.isLeaf() ? errorR : 0) + (leaves || !s.isLeaf() ? errorS : 0);
        if (rho <= maxAperture * d && decision.error <= epsilon) {
            decision.choice = LinkChoice::Far;
            return decision;
        }
        if (small) {
            decision.error = kFarEstimateBound * decision.power;
            decision.choice = LinkChoice::Far;
            return decision;
        }
        if (rho <= maxAperture * d && !leaves) {
            // Split the side that carries the larger share.
            const bool splitR = !r.isLeaf() && (s.isLeaf() || errorR >= errorS);
            decision.choice = splitR ? LinkChoice::SplitReceiver : LinkChoice::SplitSource;
            return decision;
        }
    }
    if (small) {
        // One side reaches behind the other's plane (a floor running past a column's face,
        // neighbouring faces of a vault), or a curved node's normals spread too wide to face
        // all of the other's sphere: the far link needs only every cosine along the direction
        // it uses, the centroids', to be positive (then no patch receives or sends a negative
        // share). A pair with a side whose every normal faces away from that direction gets
        // nothing; both are within epsilon. Without this such pairs went down to their leaves
        // as near links (20 of the 21 M near pairs of the 30,000-triangle interior, 97% of
        // them under a tenth of epsilon).
        const Vec3d between = s.centroid - r.centroid;
        const double distance = length(between);
        if (distance > 0) {
            const Vec3d u = between / distance;
            const int rSide = facingNormals(r, u, 0), sSide = facingNormals(s, u * -1.0, 0);
            if ((rSide > 0 && sSide > 0) || rSide < 0 || sSide < 0) {
                decision.error = kFarEstimateBound * decision.power;
                // Two planar nodes are linked all the same: their link's weight comes from
                // its segments' own cosines (hierarchical_links.h), which see the parts that
                // face each other. Dropped, such pairs held the 250,002-triangle interior's
                // floor rows 0.5% low.
                const bool planar = r.isPlanar() && s.isPlanar();
                decision.choice =
                    (rSide > 0 && sSide > 0) || planar ? LinkChoice::Far : LinkChoice::None;
                return decision;
            }
        }
    }
    // A side that faces the other only in part is what keeps the pair from a far link: split
    // it, not the other, else the other would be cut down to its leaves around a receiver that
    // still faces it in part (every link then lands on the leaves of that side).
    if (rFaces == 0 && sFaces > 0 && !r.isLeaf()) {
        decision.choice = LinkChoice::SplitReceiver;
    } else if (sFaces == 0 && rFaces > 0 && !s.isLeaf()) {
        decision.choice = LinkChoice::SplitSource;
    } else {
        decision.choice = splitChoice(r, s);
    }
    return decision;
}

LinkImportance linkImportance(const RadiositySystem& system, std::span<const uint8_t> lit,
                              std::span<const uint8_t> dark) {
    const std::size_t n = system.patchCount, m = system.wavelengthCount;
    const std::vector<double>& widths = system.binWidthsNm;
    std::vector<double> ybar(m);
    double peak = 0;
    for (std::size_t k = 0; k < m; ++k)
        peak = std::max(peak, ybar[k] = ybarAt(system.wavelengthsNm[k]));
    for (double& y : ybar)
        y = peak > 0 ? y / peak : 1.0;

    // W_k: seen directly or after one fluorescent bounce.
    std::vector<double> worth = ybar;
    for (const MaterialOperator& op : system.operators) {
        if (op.isDiagonal) continue;
        const std::vector<double> columns = weightedColumns(op, ybar, widths);
        for (std::size_t k = 0; k < m; ++k)
            worth[k] = std::max(worth[k], widths[k] > 0 ? columns[k] / widths[k] : 0.0);
    }

    // The ambient irradiance Gbar.
    std::vector<double> ambient(m, 0.0), reflectance(m, 0.0);
    double totalArea = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double area = system.areas[i];
        totalArea += area;
        const MaterialOperator& op = system.operators[system.patchOperator[i]];
        for (std::size_t k = 0; k < m; ++k) {
            ambient[k] += area * system.emission[i * m + k];
            reflectance[k] += area * (op.isZero ? 0.0 : op.diagonal[k]);
        }
    }
    for (std::size_t k = 0; k < m; ++k) {
        const double rho = totalArea > 0 ? std::min(0.95, reflectance[k] / totalArea) : 0.0;
        ambient[k] = totalArea > 0 ? ambient[k] / totalArea / (1 - rho) : 0.0;
    }

    // Per operator: its one bounce of the ambient light and its yield.
    std::vector<std::vector<double>> bounce(system.operators.size());
    std::vector<double> yield(system.operators.size(), 0.0);
    for (std::size_t p = 0; p < system.operators.size(); ++p) {
        const MaterialOperator& op = system.operators[p];
        bounce[p].resize(m);
        applyOperator(op, ambient.data(), bounce[p].data());
        const std::vector<double> columns = weightedColumns(op, worth, widths);
        for (std::size_t k = 0; k < m; ++k) {
            const double base = worth[k] * widths[k];
            if (base > 0) yield[p] = std::max(yield[p], columns[k] / base);
        }
        yield[p] = std::clamp(yield[p], 0.0, 1.0);
    }

    // The emitters' own light counts only by the share of it that comes back as indirect light
    // (the mean reflectance, weighed by W): the image's final gather recomputes the direct
    // light per pixel, so links need not resolve it (left alone, an emitter's links are cut
    // to single patches everywhere it shines: 1,360 of one ceiling patch's next to the
    // Cornell box's lamp).
    double reflected = 0, weight = 0;
    for (std::size_t k = 0; k < m; ++k) {
        reflected += (totalArea > 0 ? reflectance[k] / totalArea : 0.0) * worth[k] * widths[k];
        weight += worth[k] * widths[k];
    }
    const double directShare = weight > 0 ? std::min(1.0, reflected / weight) : 1.0;

    LinkImportance importance;
    importance.source.resize(n);
    importance.yield.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const uint32_t p = system.patchOperator[i];
        double source = 0;
        for (std::size_t k = 0; k < m; ++k)
            source +=
                (directShare * system.emission[i * m + k] + bounce[p][k]) * worth[k] * widths[k];
        importance.source[i] = lit.empty() || lit[i] ? source : 0.0;
        importance.yield[i] = dark.empty() || !dark[i] ? yield[p] : 0.0;
        importance.totalPower += system.areas[i] * importance.source[i];
    }
    return importance;
}

bool importanceGrew(const LinkImportance& before, const LinkImportance& after, double factor) {
    if (before.source.size() != after.source.size()) return true;
    if (!(after.totalPower > 0)) return false;  // no light: no link carries any
    if (!(before.totalPower > 0)) return true;
    const double scale = factor * after.totalPower / before.totalPower;
    for (std::size_t i = 0; i < after.source.size(); ++i) {
        if (after.source[i] > scale * before.source[i]) return true;
        if (after.yield[i] > factor * before.yield[i]) return true;
    }
    return false;
}

}  // namespace daisy
