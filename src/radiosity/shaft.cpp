#include "radiosity/shaft.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace daisy {
namespace {

// Newell's method: a robust normal of a polygon given in order (unnormalised, 2 x area).
Vec3d newellNormal(std::span<const Vec3d> polygon) {
    Vec3d n;
    for (std::size_t k = 0; k < polygon.size(); ++k) {
        const Vec3d& a = polygon[k];
        const Vec3d& b = polygon[(k + 1) % polygon.size()];
        n.x += (a.y - b.y) * (a.z + b.z);
        n.y += (a.z - b.z) * (a.x + b.x);
        n.z += (a.x - b.x) * (a.y + b.y);
    }
    return n;
}

}  // namespace

ShaftPolygon::ShaftPolygon(std::span<const Vec3d> points, const Vec3d& unitNormal)
    : count(static_cast<int>(std::min<std::size_t>(points.size(), kMaxPolygonVertices))),
      normal(unitNormal) {
    for (int k = 0; k < count; ++k) {
        corners[k] = points[k];
        bounds.extend(points[k]);
    }
    offset = count > 0 ? dot(normal, corners[0]) : 0.0;
}

// Adds the plane through `through` with (unnormalised) normal `n` when every shaft point is on
// one side of it, within the tolerance; rejection, the common case, needs no square root.
void Shaft::addPlane(const Vec3d& n, const Vec3d& through) {
    const double len2 = dot(n, n);
    if (!(len2 > 0)) return;
    const double limit2 = tolerance_ * tolerance_ * len2;  // (tolerance x |n|)^2
    const double base = dot(n, through);
    bool below = false, above = false;
    for (int k = 0; k < pointCount_; ++k) {
        const double d = dot(n, points_[k]) - base;
        if (d * d > limit2) {
            (d > 0 ? above : below) = true;
            if (above && below) return;
        }
    }
    addFace(above ? -n : n, std::sqrt(len2), above ? -base : base);
}

void Shaft::addFace(const Vec3d& outward, double length, double base) {
    const double inverse = 1.0 / length;
    const Vec3d normal = outward * inverse;
    const double offset = base * inverse;
    for (int k = 0; k < planeCount_; ++k) {
        if (dot(planes_[k].normal, normal) > 1 - 1e-12 &&
            std::fabs(planes_[k].offset - offset) <= tolerance_) {
            return;
        }
    }
    if (planeCount_ < kMaxPlanes) planes_[planeCount_++] = {normal, offset};
}

bool Shaft::build(std::span<const Vec3d> p, std::span<const Vec3d> q, double tolerance) {
    valid_ = false;
    planeCount_ = 0;
    pointCount_ = 0;
    bounds_ = {};
    tolerance_ = tolerance;
    if (p.size() < 3 || q.size() < 3 || p.size() + q.size() > std::size_t(kMaxPoints)) {
        return false;
    }
    for (const Vec3d& v : p)
        points_[pointCount_++] = v;
    for (const Vec3d& v : q)
        points_[pointCount_++] = v;
    for (int k = 0; k < pointCount_; ++k)
        bounds_.extend(points_[k]);

    addPlane(newellNormal(p), p[0]);
    addPlane(newellNormal(q), q[0]);
    // Planes through an edge (a, b) of one polygon and a vertex of the other. The polygon of the
    // edge lies on one side of any such plane (other than its own plane, added above): the side
    // of `inner`, its vertex before a (off the edge's line, as the outlines have no collinear
    // vertices). Turning a plane about the edge's line, the hull's faces through the edge are the
    // planes through the apexes furthest round on either side of the edge polygon's plane, when
    // no apex lies beyond them: one candidate a side (apex o is further round than c when it is
    // strictly on the far side of c's plane from `inner`; the order is total within a side), then
    // the check of the other apexes. O(m n) a polygon instead of O(m n^2).
    const auto edgeVertexPlanes = [&](std::span<const Vec3d> edges, std::span<const Vec3d> apexes) {
        struct Candidate {
            Vec3d n;
            double inside = 0;
            double len2 = 0;
        };
        const std::size_t m = edges.size();
        for (std::size_t e = 0; e < m; ++e) {
            const Vec3d& a = edges[e];
            const Vec3d edge = edges[(e + 1) % m] - a;
            const Vec3d inner = edges[(e + m - 1) % m] - a;
            Candidate best[2];  // [0]: apexes with inside < 0, [1]: inside > 0
            for (const Vec3d& apex : apexes) {
                const Vec3d r = apex - a;
                const Vec3d n = cross(edge, r);
                const double len2 = dot(n, n);
                const double inside = dot(n, inner);
                // Skip planes that are the edge polygon's own (the apex lies on it).
                if (!(inside * inside > tolerance_ * tolerance_ * len2)) continue;
                Candidate& c = best[inside > 0 ? 1 : 0];
                if (c.len2 == 0 || dot(c.n, r) * c.inside < 0) c = {n, inside, len2};
            }
            for (const Candidate& c : best) {
                if (c.len2 == 0) continue;
                const double limit2 = tolerance_ * tolerance_ * c.len2;
                bool face = true;
                for (std::size_t o = 0; o < apexes.size() && face; ++o) {
                    const double d = dot(c.n, apexes[o] - a);
                    face = !(d * c.inside < 0 && d * d > limit2);
                }
                if (!face) continue;
                const Vec3d outward = c.inside > 0 ? -c.n : c.n;
                addFace(outward, std::sqrt(c.len2), dot(outward, a));
            }
        }
    };
    edgeVertexPlanes(p, q);
    edgeVertexPlanes(q, p);
    // A hull with interior needs at least 4 faces; a flat set (P and Q coplanar) has two
    // opposite copies of one plane and nothing else.
    valid_ = planeCount_ >= 4;
    return valid_;
}

bool Shaft::excludesBox(const Bounds3d& box) const {
    if (!valid_) return false;
    for (int axis = 0; axis < 3; ++axis) {
        if (box.hi[axis] <= bounds_.lo[axis] + tolerance_ ||
            box.lo[axis] >= bounds_.hi[axis] - tolerance_) {
            return true;
        }
    }
    for (int k = 0; k < planeCount_; ++k) {
        const Vec3d& n = planes_[k].normal;
        const Vec3d nearest{n.x >= 0 ? box.lo.x : box.hi.x, n.y >= 0 ? box.lo.y : box.hi.y,
                            n.z >= 0 ? box.lo.z : box.hi.z};
        if (dot(n, nearest) - planes_[k].offset >= -tolerance_) return true;
    }
    return false;
}

bool Shaft::excludesPolygon(const ShaftPolygon& polygon) const {
    if (!valid_) return false;
    for (int axis = 0; axis < 3; ++axis) {
        if (polygon.bounds.hi[axis] <= bounds_.lo[axis] + tolerance_ ||
            polygon.bounds.lo[axis] >= bounds_.hi[axis] - tolerance_) {
            return true;
        }
    }
    for (int k = 0; k < planeCount_; ++k) {
        const Vec3d& n = planes_[k].normal;
        const double o = planes_[k].offset - tolerance_;
        bool outside = true;
        for (int v = 0; v < polygon.count && outside; ++v)
            outside = dot(n, polygon.corners[v]) >= o;
        if (outside) return true;
    }
    // The polygon's own plane separates when every hull point is on one side of it.
    if (polygon.normal == Vec3d{}) return false;
    bool below = true, above = true;
    for (int k = 0; k < pointCount_ && (below || above); ++k) {
        const double d = dot(polygon.normal, points_[k]) - polygon.offset;
        below = below && d <= tolerance_;
        above = above && d >= -tolerance_;
    }
    return below || above;
}

int planarConvexHull(std::span<const Vec3d> points, const Vec3d& normal, std::span<Vec3d> out) {
    if (points.empty() || out.size() < 4) return 0;
    // An orthonormal basis (u, v) of the plane.
    const Vec3d helper = std::fabs(normal.x) < 0.6 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
    const Vec3d u = normalize(cross(normal, helper));
    const Vec3d v = cross(normal, u);
    struct Point2 {
        double x, y;
        uint32_t index;
    };
    std::vector<Point2> p2(points.size());
    for (std::size_t k = 0; k < points.size(); ++k)
        p2[k] = {dot(points[k], u), dot(points[k], v), static_cast<uint32_t>(k)};
    std::sort(p2.begin(), p2.end(),
              [](const Point2& a, const Point2& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
    const auto turn = [](const Point2& o, const Point2& a, const Point2& b) {
        return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    };
    // Andrew's monotone chain; collinear points are dropped (turn <= 0).
    std::vector<Point2> hull(2 * p2.size() + 1);
    std::size_t h = 0;
    for (std::size_t k = 0; k < p2.size(); ++k) {
        while (h >= 2 && turn(hull[h - 2], hull[h - 1], p2[k]) <= 0)
            --h;
        hull[h++] = p2[k];
    }
    for (std::size_t k = p2.size() - 1, lower = h + 1; k-- > 0;) {
        while (h >= lower && turn(hull[h - 2], hull[h - 1], p2[k]) <= 0)
            --h;
        hull[h++] = p2[k];
    }
    const std::size_t count = h > 1 ? h - 1 : h;  // the last point repeats the first
    if (count <= out.size()) {
        for (std::size_t k = 0; k < count; ++k)
            out[k] = points[hull[k].index];
        return static_cast<int>(count);
    }
    // Too many vertices: the bounding rectangle in (u, v), lifted onto the plane.
    double xLo = p2.front().x, xHi = p2.back().x, yLo = p2[0].y, yHi = p2[0].y;
    for (const Point2& q : p2) {
        yLo = std::min(yLo, q.y);
        yHi = std::max(yHi, q.y);
    }
    const double w = dot(points[0], normal);
    const std::array<std::array<double, 2>, 4> corners{
        {{xLo, yLo}, {xHi, yLo}, {xHi, yHi}, {xLo, yHi}}};
    for (int k = 0; k < 4; ++k)
        out[k] = u * corners[k][0] + v * corners[k][1] + normal * w;
    return 4;
}

}  // namespace daisy
