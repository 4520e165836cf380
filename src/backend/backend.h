#pragma once
// Backends build the view-factor matrix (DESIGN.md section 8). `cpu` (Embree rays, TBB threads)
// is built today; `reference`, `vulkan` and `cuda` land with their issues and until then are
// refused with a clear message. `auto` picks the best built backend: cuda, then vulkan on a GPU,
// then cpu; today that is always cpu.
#include <memory>
#include <string>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "radiosity/form_factors.h"

namespace daisy {

class Backend {
public:
    virtual ~Backend() = default;
    virtual std::string name() const = 0;
    // Builds F for the mesh; errors are bad settings or input (exit status 2 in the app).
    virtual Expected<FormFactorResult> buildFormFactors(const PatchMesh& mesh,
                                                        const FormFactorSettings& settings) = 0;
};

// Every backend name the command line accepts, "auto" first.
std::vector<std::string> backendNames();

// The backend called `name` ("auto" resolves as above). Error for unknown names and for
// backends not built into this binary: "backend 'vulkan' is not built yet".
Expected<std::unique_ptr<Backend>> makeBackend(const std::string& name);

std::unique_ptr<Backend> makeCpuBackend();

}  // namespace daisy
