#include "raycast/ray_caster.h"

#include "raycast/embree_ray_caster.h"

namespace daisy {

const char* packetModeName(PacketMode mode) {
    switch (mode) {
        case PacketMode::Single:
            return "single";
        case PacketMode::Packet4:
            return "packet4";
        case PacketMode::Packet8:
            return "packet8";
        case PacketMode::Packet16:
            return "packet16";
        case PacketMode::Stream:
            return "stream";
    }
    return "?";
}

Expected<std::unique_ptr<RayCaster>> makeRayCaster(const PatchMesh& mesh,
                                                   const RayCasterOptions& options) {
    auto caster = EmbreeRayCaster::create(mesh, options);
    if (!caster) return caster.error();
    return std::unique_ptr<RayCaster>(std::move(*caster));
}

}  // namespace daisy
