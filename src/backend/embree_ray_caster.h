#pragma once
// The cpu backend's ray tracer: an Embree 3 scene of the patches (one triangle geometry, primID
// = patch index, float positions, high-quality BVH) answering the driver's occlusion and
// closest-hit queries. Embree types stay inside the .cpp.
#include <memory>
#include <string>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "radiosity/ray_caster.h"

namespace daisy {

// How occlusion queries are issued: one ray at a time (rtcOccluded1), SIMD packets of 4/8/16
// rays (rtcOccluded4/8/16, coherent context), or Embree's stream API (rtcOccluded1M).
enum class PacketMode { Single, Packet4, Packet8, Packet16, Stream };

// A closest hit with its position on the patch: the hit point is
// (1 - u - v) * corner0 + u * corner1 + v * corner2 with the patch's corners in PatchMesh order
// (Embree's barycentrics of the triangle as built), at distance t along the ray (scene units
// for a unit direction). patch = kNoPatch (u = v = 0, t = infinity) for a miss.
struct SurfaceHit {
    uint32_t patch;
    float u, v, t;
};

const char* packetModeName(PacketMode mode);

class EmbreeRayCaster final : public RayCaster {
public:
    // Builds the scene. Fails (no crash) when Embree cannot create a device or scene.
    // `robust` sets RTC_SCENE_FLAG_ROBUST: watertight triangle tests, so a ray through an edge
    // shared by two patches hits one of them (primary rays; the view factors do not need it).
    static Expected<std::unique_ptr<EmbreeRayCaster>> create(const PatchMesh& mesh,
                                                             PacketMode mode = PacketMode::Packet16,
                                                             bool robust = false);
    ~EmbreeRayCaster() override;

    void occluded(const SegmentArrays& segments, std::span<uint8_t> blocked) const override;
    void closestHits(std::span<const Ray> rays, std::span<uint32_t> hits) const override;
    // hits[k] = the first patch rays[k] hits at t >= tNear, with its barycentrics (camera rays:
    // tNear = 0, no self-intersection margin). Thread-safe; rays.size() == hits.size().
    void closestSurfaceHits(std::span<const Ray> rays, std::span<SurfaceHit> hits,
                            float tNear = 0) const;

    PacketMode packetMode() const;
    void setPacketMode(PacketMode mode);

    struct Impl;

private:
    explicit EmbreeRayCaster(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace daisy
