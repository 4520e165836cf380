#include "vulkan/pipelines.h"

#include <vector>

#include "core/check.h"
#include "vulkan/vk_check.h"

namespace daisy {

namespace {

// The layout and pipeline of createComputePipeline into `result` over `module`; what it made stays
// in `result` when it fails, for the caller to destroy.
Expected<void> makePipeline(const VulkanContext& context, VkShaderModule module,
                            std::span<const int32_t> specialization, ComputePipeline& result) {
    const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, result.pushConstantBytes};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.pushConstantRangeCount = result.pushConstantBytes > 0 ? 1 : 0;
    layoutInfo.pPushConstantRanges = &range;
    VK_CHECK(vkCreatePipelineLayout(context.device, &layoutInfo, nullptr, &result.layout));

    VkComputePipelineCreateInfo pipelineInfo{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    pipelineInfo.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    pipelineInfo.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    pipelineInfo.stage.module = module;
    pipelineInfo.stage.pName = "main";
    std::vector<VkSpecializationMapEntry> entries;
    for (uint32_t id = 0; id < specialization.size(); ++id)
        entries.push_back({id, uint32_t(id * sizeof(int32_t)), sizeof(int32_t)});
    const VkSpecializationInfo specializationInfo{uint32_t(entries.size()), entries.data(),
                                                  specialization.size_bytes(),
                                                  specialization.data()};
    if (!specialization.empty()) pipelineInfo.stage.pSpecializationInfo = &specializationInfo;
    pipelineInfo.layout = result.layout;
    VK_CHECK(vkCreateComputePipelines(context.device, VK_NULL_HANDLE, 1, &pipelineInfo, nullptr,
                                      &result.pipeline));
    return {};
}

}  // namespace

Expected<ComputePipeline> createComputePipeline(const VulkanContext& context,
                                                std::span<const uint32_t> spirv,
                                                uint32_t pushConstantBytes,
                                                std::span<const int32_t> specialization) {
    DAISY_CHECK(!spirv.empty());
    DAISY_CHECK_OP(pushConstantBytes, <=, context.properties.limits.maxPushConstantsSize);
    VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    moduleInfo.codeSize = spirv.size_bytes();
    moduleInfo.pCode = spirv.data();
    VkShaderModule module = VK_NULL_HANDLE;
    VK_CHECK(vkCreateShaderModule(context.device, &moduleInfo, nullptr, &module));
    ComputePipeline result;
    result.pushConstantBytes = pushConstantBytes;
    auto made = makePipeline(context, module, specialization, result);
    vkDestroyShaderModule(context.device, module, nullptr);
    if (!made) {
        destroyComputePipeline(context, result);
        return made.error();
    }
    return result;
}

void destroyComputePipeline(const VulkanContext& context, ComputePipeline& pipeline) {
    if (pipeline.pipeline) vkDestroyPipeline(context.device, pipeline.pipeline, nullptr);
    if (pipeline.layout) vkDestroyPipelineLayout(context.device, pipeline.layout, nullptr);
    pipeline = ComputePipeline{};
}

}  // namespace daisy
