#pragma once
// The vulkan backend (DESIGN.md section 8): the shared pair kernel (shared/pair_kernel.h) as a
// headless compute shader over our flat BVH, on any Vulkan 1.2 device (Mesa lavapipe in CI).
#include <memory>

#include "backend/backend.h"
#include "core/expected.h"

namespace daisy {

// The backend on the device options.device selects (index or part of its name; empty = the
// first discrete GPU, else integrated, else any). Error with a clear message when Vulkan or a
// matching device is missing.
Expected<std::unique_ptr<Backend>> makeVulkanBackend(const BackendOptions& options);

// True when a discrete or integrated GPU offers Vulkan 1.2 (what `--backend auto` asks).
bool vulkanHardwareGpuPresent();

}  // namespace daisy
