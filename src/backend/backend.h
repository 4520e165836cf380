#pragma once
// Backends build the view-factor matrix (DESIGN.md section 8): `cpu` (CPU rays, TBB threads),
// `reference` (the shared kernels of src/shared/ on the CPU over our flat BVH: the oracle for the
// GPU backends), `vulkan` (the same kernels as compute shaders; only in binaries built with
// DAISY_ENABLE_VULKAN, and only where a Vulkan 1.2 device exists) and `cuda` (the same kernel
// under nvcc, cuda/; only where CMake found nvcc and a CUDA device exists). The list of backends
// and `--backend auto` live in pipeline/backend_registry.h, above every backend library.
#include <memory>
#include <string>

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
    // One line on the device and how it traces rays, for `daisy info` (empty: nothing to say).
    virtual std::string describe() const { return {}; }
};

// How the vulkan backend traces shadow segments (--vulkan-rays): ray queries through the
// device's acceleration structures on a GPU that has them, else the flat-BVH walk in the shader
// (Auto; a CPU device's ray queries are slower than the walk); ray queries or an error
// (Query); the walk (Software).
enum class VulkanRays { Auto, Query, Software };

struct BackendOptions {
    std::string device;  // --device: GPU index or part of its name; empty = the first suitable
    VulkanRays vulkanRays = VulkanRays::Auto;
};

std::unique_ptr<Backend> makeCpuBackend();
std::unique_ptr<Backend> makeReferenceBackend();

}  // namespace daisy
