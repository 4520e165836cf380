#pragma once
// The ray caster on Embree 3: one scene of the patches (one triangle geometry, primID = patch
// index, float positions, high-quality BVH) answering the RayCaster queries. Built only through
// makeRayCaster (raycast/ray_caster.h); Embree types stay inside the .cpp.
#include <memory>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "raycast/ray_caster.h"

namespace daisy {

class EmbreeRayCaster final : public RayCaster {
public:
    // Builds the scene. Fails (no crash) when Embree cannot create a device or scene.
    // options.robust sets RTC_SCENE_FLAG_ROBUST; options.packetMode picks rtcOccluded1,
    // rtcOccluded4/8/16 or the stream API rtcOccluded1M (incoherent contexts: the segments of a
    // packet point every way); options.watertightSegments decides segments with the shared
    // watertight test.
    static Expected<std::unique_ptr<EmbreeRayCaster>> create(const PatchMesh& mesh,
                                                             const RayCasterOptions& options);
    ~EmbreeRayCaster() override;

    void occluded(const SegmentArrays& segments, std::span<uint8_t> blocked) const override;
    void closestHits(std::span<const Ray> rays, std::span<uint32_t> hits) const override;
    void closestSurfaceHits(std::span<const Ray> rays, std::span<SurfaceHit> hits,
                            float tNear) const override;

    PacketMode packetMode() const override;
    void setPacketMode(PacketMode mode) override;

    struct Impl;

private:
    explicit EmbreeRayCaster(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace daisy
