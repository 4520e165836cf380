#pragma once
// Shaft culling (Haines & Wallace 1994, "Shaft Culling for Efficient Ray-Cast Radiosity"): the
// shaft of two convex planar polygons P and Q is their convex hull conv(P u Q), which is exactly
// the union of the segments from a point of P to a point of Q. Geometry that stays outside the
// shaft's interior cannot block any visibility ray between them, so when nothing enters the
// shaft the pair's visibility is 1 without casting a ray.
//
// The hull is built from its faces: the plane of P, the plane of Q, and planes through an edge of
// one polygon and a vertex of the other (every face of the hull of two convex planar polygons is
// one of these). The tests are conservative: "outside" is only claimed with a separating plane
// (a hull face, the object's own plane, or an axis of the hull's bounding box), so a false
// "may enter" only costs rays, never a wrong answer. Objects that merely touch the hull's
// boundary (a neighbour sharing an edge) count as outside: they cannot stop a segment between
// interior points of P and Q.
#include <cstdint>
#include <span>

#include "geometry/bounds.h"
#include "geometry/vec3.h"

namespace daisy {

inline constexpr int kMaxPolygonVertices = 16;

// A convex planar polygon (a patch, or a solid face tiled by patches) prepared for repeated shaft
// tests: corners in order, bounds and its plane.
struct ShaftPolygon {
    Vec3d corners[kMaxPolygonVertices];
    int count = 0;
    Bounds3d bounds;
    Vec3d normal;  // unit; zero for a degenerate polygon
    double offset = 0;  // plane: dot(normal, x) = offset

    ShaftPolygon() = default;
    // At most kMaxPolygonVertices corners; the normal is taken from `normal`.
    ShaftPolygon(std::span<const Vec3d> points, const Vec3d& unitNormal);
    std::span<const Vec3d> points() const { return {corners, std::size_t(count)}; }
};

struct ShaftPlane {
    Vec3d normal;  // unit, pointing out of the shaft
    double offset = 0;  // plane: dot(normal, x) = offset
};

class Shaft {
public:
    static constexpr int kMaxPoints = 64;  // P and Q together
    static constexpr int kMaxPlanes = 96;

    // Hull of the convex planar polygons p and q (vertices in order around each). `tolerance`
    // (scene units) is how far a point may be inside a plane and still count as on it: use a
    // small multiple of float rounding at the scene's scale. Returns false (no shaft: test
    // nothing as outside) when the hull is flat or the polygons exceed kMaxPoints.
    bool build(std::span<const Vec3d> p, std::span<const Vec3d> q, double tolerance);

    bool valid() const { return valid_; }
    int planeCount() const { return planeCount_; }
    const Bounds3d& bounds() const { return bounds_; }

    // True when the box provably does not enter the shaft's interior.
    bool excludesBox(const Bounds3d& box) const;
    // True when the polygon provably does not enter the shaft's interior.
    bool excludesPolygon(const ShaftPolygon& polygon) const;

private:
    void addPlane(const Vec3d& normal, const Vec3d& through);
    // Adds the face with outward normal `outward` (length `length`) and dot(outward, x) = base.
    void addFace(const Vec3d& outward, double length, double base);

    ShaftPlane planes_[kMaxPlanes];
    Vec3d points_[kMaxPoints];
    int planeCount_ = 0;
    int pointCount_ = 0;
    double tolerance_ = 0;
    Bounds3d bounds_;
    bool valid_ = false;
};

// The convex hull, in their common plane, of points lying (up to rounding) on a plane with unit
// normal `normal`; returns the hull's vertices in order (Andrew's monotone chain) in `out`, at
// most out.size() of them, and how many. When the hull has more vertices than fit, returns a
// conservative enclosing polygon (the hull's bounding rectangle in the plane).
int planarConvexHull(std::span<const Vec3d> points, const Vec3d& normal, std::span<Vec3d> out);

}  // namespace daisy
