#pragma once
// Compute pipelines from SPIR-V embedded in the binary (STYLE.md rule 5: no runtime paths). The
// shaders take all their inputs as push constants holding buffer device addresses, so the layout
// is one push-constant range and no descriptor sets.
#include <volk.h>

#include <cstdint>
#include <span>
#include <string_view>

#include "core/expected.h"
#include "vulkan/context.h"

namespace daisy {

struct ComputePipeline {
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
    uint32_t pushConstantBytes = 0;
};

// The SPIR-V of shaders/<name>.glsl, e.g. embeddedSpirv("form_factors.comp"), or of one of its
// variants, e.g. embeddedSpirv("form_factors.comp/ray_query"), compiled by cmake/Shaders.cmake.
// Empty when no shader has that name.
std::span<const uint32_t> embeddedSpirv(std::string_view name);

// A compute pipeline over `spirv` (entry point "main") with a push-constant range of
// pushConstantBytes (<= maxPushConstantsSize) bytes. specialization[k] is the value of the
// 32-bit specialization constant with constant_id k (the shader's defaults where absent). An
// Error (VK_CHECK) when the driver fails to make it; nothing is left allocated then.
Expected<ComputePipeline> createComputePipeline(const VulkanContext& context,
                                                std::span<const uint32_t> spirv,
                                                uint32_t pushConstantBytes,
                                                std::span<const int32_t> specialization = {});
void destroyComputePipeline(const VulkanContext& context, ComputePipeline& pipeline);

}  // namespace daisy
