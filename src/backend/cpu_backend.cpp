// The cpu backend: the form-factor driver (radiosity/form_factors.h) with the ray caster's
// visibility (raycast/ray_caster.h), Embree's stream of single rays (measured fastest here:
// docs/performance.md) and TBB threads. Its segments are decided by the shared watertight
// test (watertightSegments), so its visibility is the reference backend's, segment for segment,
// on every instruction set.
#include "backend/backend.h"
#include "raycast/ray_caster.h"

namespace daisy {
namespace {

class CpuBackend final : public Backend {
public:
    std::string name() const override { return "cpu"; }

    Expected<FormFactorResult> buildFormFactors(const PatchMesh& mesh,
                                                const FormFactorSettings& settings) override {
        auto caster =
            makeRayCaster(mesh, {.packetMode = PacketMode::Stream, .watertightSegments = true});
        if (!caster) return caster.error();
        return computeFormFactors(mesh, settings, **caster);
    }
};

}  // namespace

std::unique_ptr<Backend> makeCpuBackend() {
    return std::make_unique<CpuBackend>();
}

}  // namespace daisy
