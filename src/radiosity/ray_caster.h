#pragma once
// What the form-factor driver needs from a ray tracer (a backend implements it; the cpu backend
// with Embree): occlusion of segments between sample points, and closest hits for the stochastic
// method. Geometry is the PatchMesh the caster was built from; hits report patch indices.
#include <cstdint>
#include <span>
#include <vector>

namespace daisy {

// Shadow segments as six arrays (structure of arrays, as ray packets take them): segment k runs
// from (x0[k], y0[k], z0[k]) to (x1[k], y1[k], z1[k]), scene units, float.
struct SegmentArrays {
    std::vector<float> x0, y0, z0, x1, y1, z1;

    std::size_t size() const { return x0.size(); }
    void resize(std::size_t n) {
        for (std::vector<float>* v : {&x0, &y0, &z0, &x1, &y1, &z1})
            v->resize(n);
    }
    void set(std::size_t k, float ox, float oy, float oz, float ex, float ey, float ez) {
        x0[k] = ox, y0[k] = oy, z0[k] = oz, x1[k] = ex, y1[k] = ey, z1[k] = ez;
    }
    bool empty(std::size_t k) const { return x0[k] == x1[k] && y0[k] == y1[k] && z0[k] == z1[k]; }
};

// A ray for closest-hit queries: origin (scene units) and unit direction.
struct Ray {
    float origin[3];
    float direction[3];
};

inline constexpr uint32_t kNoPatch = 0xffffffffu;

class RayCaster {
public:
    virtual ~RayCaster() = default;

    // blocked[k] = 1 when some patch blocks segments[k] strictly between its end points (a
    // relative margin of kSegmentMargin at each end guards against rounding; the driver trims
    // segments off their patches itself), else 0. An empty segment (origin == end) is never
    // blocked. Thread-safe; called concurrently from worker threads.
    virtual void occluded(const SegmentArrays& segments, std::span<uint8_t> blocked) const = 0;

    // hits[k] = index of the first patch rays[k] hits beyond a small self-intersection margin,
    // or kNoPatch. Thread-safe.
    virtual void closestHits(std::span<const Ray> rays, std::span<uint32_t> hits) const = 0;

    // Margin at each end of a shadow segment, as a fraction of its length.
    static constexpr float kSegmentMargin = 1e-5f;
};

}  // namespace daisy
