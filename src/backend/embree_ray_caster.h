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

const char* packetModeName(PacketMode mode);

class EmbreeRayCaster final : public RayCaster {
public:
    // Builds the scene. Fails (no crash) when Embree cannot create a device or scene.
    static Expected<std::unique_ptr<EmbreeRayCaster>> create(
        const PatchMesh& mesh, PacketMode mode = PacketMode::Packet16);
    ~EmbreeRayCaster() override;

    void occluded(const SegmentArrays& segments, std::span<uint8_t> blocked) const override;
    void closestHits(std::span<const Ray> rays, std::span<uint32_t> hits) const override;

    PacketMode packetMode() const;
    void setPacketMode(PacketMode mode);

    struct Impl;

private:
    explicit EmbreeRayCaster(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace daisy
