#include "radiosity/kernel_inputs.h"

#include "shared/config.h"
#include "shared/rng.h"

namespace daisy {

using shared::PatchGeometry;
using shared::vec3;

int kernelMethod(FormFactorMethod method) {
    switch (method) {
        case FormFactorMethod::Riemann:
            return DAISY_METHOD_RIEMANN;
        case FormFactorMethod::Nusselt:
            return DAISY_METHOD_NUSSELT;
        case FormFactorMethod::Stochastic:
            return DAISY_METHOD_STOCHASTIC;
        case FormFactorMethod::Hybrid:
            return DAISY_METHOD_HYBRID;
    }
    return DAISY_METHOD_HYBRID;
}

uint32_t kernelSeed(uint64_t seed) {
    return shared::pcgHash(static_cast<uint32_t>(seed) ^
                           shared::pcgHash(static_cast<uint32_t>(seed >> 32)));
}

std::vector<PatchGeometry> kernelPatches(const PatchMesh& mesh) {
    const auto toVec3 = [](const Vec3d& v) {
        return vec3(static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z));
    };
    std::vector<PatchGeometry> geometry(mesh.patchCount());
    for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
        PatchGeometry& g = geometry[p];
        g = shared::makePatchGeometry(toVec3(mesh.positions[mesh.patches[p][0]]),
                                      toVec3(mesh.positions[mesh.patches[p][1]]),
                                      toVec3(mesh.positions[mesh.patches[p][2]]));
        g.normal = toVec3(mesh.normals[p]);
        g.area = static_cast<float>(mesh.areas[p]);
    }
    return geometry;
}

KernelSettings kernelSettings(const FormFactorSettings& settings) {
    KernelSettings k;
    k.method = kernelMethod(settings.method);
    k.level = settings.quadratureLevel;
    k.seed = kernelSeed(settings.seed);
    k.clearanceRelative = kEndClearanceRelative;
    return k;
}

}  // namespace daisy
