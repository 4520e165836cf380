#pragma once
// The ray tracer over a PatchMesh that the form-factor driver, the image renderer, the final
// gather, the path tracer and the punctual lights share: occlusion of segments between sample
// points, closest-hit patches, and closest hits with their barycentrics. makeRayCaster builds
// the one implementation (raycast/embree_ray_caster.h); callers hold only this interface.
// Geometry is the PatchMesh the caster was built from, as float positions; hits report patch
// indices into it.
#include <cstdint>
#include <memory>
#include <span>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "raycast/ray.h"

namespace daisy {

// How occlusion queries are issued: one ray at a time, SIMD packets of 4/8/16 rays, or a stream
// of single rays handed over in batches. With watertightSegments the answers do not depend on
// it, otherwise only on segments within float rounding of an edge; the speed does
// (docs/performance.md).
enum class PacketMode { Single, Packet4, Packet8, Packet16, Stream };

// "single", "packet4", "packet8", "packet16" or "stream".
const char* packetModeName(PacketMode mode);

struct RayCasterOptions {
    PacketMode packetMode = PacketMode::Packet16;
    // Watertight triangle tests, so a ray through an edge shared by two patches hits one of them
    // (primary and gather rays).
    bool robust = false;
    // occluded() and closestHits() decide every hit with the shared watertight test
    // (shared/intersect.h), the reference backend's: Embree only proposes candidates, over
    // triangles grown slightly, and a filter keeps those the watertight test hits. So a
    // segment's answer is a function of the segment alone, the same for every packet mode and
    // every instruction set Embree runs (the view factors of the cpu backend). Not for
    // closestSurfaceHits (its barycentrics would be the grown triangle's).
    bool watertightSegments = false;
};

class RayCaster {
public:
    virtual ~RayCaster() = default;

    // blocked[k] = 1 when some patch blocks segments[k] strictly between its end points (a
    // relative margin of kSegmentMargin at each end guards against rounding; the driver trims
    // segments off their patches itself), else 0. An empty segment (origin == end) is never
    // blocked. Thread-safe; called concurrently from worker threads.
    virtual void occluded(const SegmentArrays& segments, std::span<uint8_t> blocked) const = 0;

    // hits[k] = index of the first patch rays[k] hits beyond a small self-intersection margin
    // (1e-6 of the scene's bounding-box diagonal), or kNoPatch. Thread-safe.
    virtual void closestHits(std::span<const Ray> rays, std::span<uint32_t> hits) const = 0;

    // hits[k] = the first patch rays[k] hits at t >= tNear (scene units), with its barycentrics
    // (camera rays: tNear = 0, no self-intersection margin). Thread-safe;
    // rays.size() == hits.size().
    virtual void closestSurfaceHits(std::span<const Ray> rays, std::span<SurfaceHit> hits,
                                    float tNear = 0) const = 0;

    // How occluded() issues its queries; setPacketMode is not thread-safe against queries.
    virtual PacketMode packetMode() const = 0;
    virtual void setPacketMode(PacketMode mode) = 0;

    // Margin at each end of a shadow segment, as a fraction of its length.
    static constexpr float kSegmentMargin = 1e-5f;
};

// Builds a ray caster over `mesh` (every patch, float positions). Fails (no crash) when the
// ray tracer cannot be set up or cannot build the scene.
Expected<std::unique_ptr<RayCaster>> makeRayCaster(const PatchMesh& mesh,
                                                   const RayCasterOptions& options = {});

}  // namespace daisy
