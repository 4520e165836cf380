#pragma once
// Axis-aligned bounding box; empty until the first point is added.
#include <algorithm>
#include <limits>

#include "geometry/vec3.h"

namespace daisy {

struct Bounds3d {
    Vec3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
             std::numeric_limits<double>::infinity()};
    Vec3d hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
             -std::numeric_limits<double>::infinity()};

    bool empty() const { return lo.x > hi.x; }
    void extend(const Vec3d& p) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    Vec3d extent() const { return empty() ? Vec3d{} : hi - lo; }
    Vec3d center() const { return (lo + hi) * 0.5; }
    double diagonal() const { return length(extent()); }
};

}  // namespace daisy
