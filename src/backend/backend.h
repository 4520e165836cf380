#pragma once
// Backends build the view-factor matrix (DESIGN.md section 8): `cpu` (Embree rays, TBB threads),
// `reference` (the shared kernels of src/shared/ on the CPU over our flat BVH: the oracle for the
// GPU backends), `vulkan` (the same kernels as compute shaders; only in binaries built with
// DAISY_ENABLE_VULKAN, and only where a Vulkan 1.2 device exists) and `cuda` (lands with its
// issue; until then refused with a clear message). `auto` picks vulkan on a discrete or
// integrated GPU when built in, else cpu (cuda joins first in line with its issue).
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

struct BackendOptions {
    std::string device;  // --device: GPU index or part of its name; empty = the first suitable
};

// Every backend name the command line accepts, "auto" first.
std::vector<std::string> backendNames();

// The backend called `name` ("auto" resolves as above). Error for unknown names, for backends
// not built into this binary ("backend 'vulkan' is not built into this binary (configure with
// -DDAISY_ENABLE_VULKAN=ON)", "backend 'cuda' is not built yet") and for a missing device.
Expected<std::unique_ptr<Backend>> makeBackend(const std::string& name,
                                               const BackendOptions& options = {});

std::unique_ptr<Backend> makeCpuBackend();
std::unique_ptr<Backend> makeReferenceBackend();

}  // namespace daisy
