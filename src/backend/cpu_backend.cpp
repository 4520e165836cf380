// The cpu backend: the form-factor driver (radiosity/form_factors.h) with Embree 3 visibility,
// 16-ray packets (rtcOccluded16, measured fastest here: docs/performance.md) and TBB threads.
#include "backend/backend.h"
#include "backend/embree_ray_caster.h"

namespace daisy {
namespace {

class CpuBackend final : public Backend {
public:
    std::string name() const override { return "cpu"; }

    Expected<FormFactorResult> buildFormFactors(const PatchMesh& mesh,
                                                const FormFactorSettings& settings) override {
        auto caster = EmbreeRayCaster::create(mesh, PacketMode::Packet16);
        if (!caster) return caster.error();
        return computeFormFactors(mesh, settings, **caster);
    }
};

}  // namespace

std::unique_ptr<Backend> makeCpuBackend() {
    return std::make_unique<CpuBackend>();
}

}  // namespace daisy
