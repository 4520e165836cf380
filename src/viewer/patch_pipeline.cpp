#include "viewer/patch_pipeline.h"

#include <cstring>
#include <vector>

#include "core/check.h"
#include "vulkan/pipelines.h"
#include "vulkan/vk_check.h"

namespace daisy::viewer {
namespace {

Expected<VkShaderModule> shaderModule(const VulkanContext& context, const char* name) {
    const std::span<const uint32_t> spirv = embeddedSpirv(name);
    DAISY_CHECK(!spirv.empty());
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = spirv.size_bytes();
    info.pCode = spirv.data();
    VkShaderModule module = VK_NULL_HANDLE;
    VK_CHECK(vkCreateShaderModule(context.device, &info, nullptr, &module));
    return module;
}

// The layout and pipeline of createPatchPipeline into `result` over the two shader modules; what
// it made stays in `result` when it fails, for the caller to destroy.
Expected<void> makePatchPipeline(const VulkanContext& context, VkRenderPass renderPass,
                                 VkShaderModule vertex, VkShaderModule fragment,
                                 VkDescriptorSetLayout detailLayout, PatchPipeline& result) {
    const VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                    sizeof(shared::ViewerPush)};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &range;
    if (detailLayout) {
        layoutInfo.setLayoutCount = 1;
        layoutInfo.pSetLayouts = &detailLayout;
    }
    VK_CHECK(vkCreatePipelineLayout(context.device, &layoutInfo, nullptr, &result.layout));

    VkPipelineShaderStageCreateInfo stages[2]{};
    stages[0].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = vertex;
    stages[0].pName = "main";
    stages[1].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = fragment;
    stages[1].pName = "main";

    // Positions, values, and with texture detail its uv and factor (viewer/detail_vertices.h).
    const VkVertexInputBindingDescription bindings[3] = {
        {0, 4 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX},
        {1, 4 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX},
        {2, kDetailFloats * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX}};
    const VkVertexInputAttributeDescription attributes[4] = {
        {0, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 0},
        {1, 1, VK_FORMAT_R32G32B32A32_SFLOAT, 0},
        {2, 2, VK_FORMAT_R32G32_SFLOAT, 0},
        {3, 2, VK_FORMAT_R32G32B32_SFLOAT, 2 * sizeof(float)}};
    VkPipelineVertexInputStateCreateInfo vertexInput{
        VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vertexInput.vertexBindingDescriptionCount = detailLayout ? 3 : 2;
    vertexInput.pVertexBindingDescriptions = bindings;
    vertexInput.vertexAttributeDescriptionCount = detailLayout ? 4 : 2;
    vertexInput.pVertexAttributeDescriptions = attributes;
    VkPipelineInputAssemblyStateCreateInfo assembly{
        VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo viewport{
        VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{
        VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{
        VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo depth{
        VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = VK_TRUE;
    depth.depthWriteEnable = VK_TRUE;
    depth.depthCompareOp = VK_COMPARE_OP_GREATER;  // reverse-Z (view_camera.h)
    VkPipelineColorBlendAttachmentState blendAttachment{};
    blendAttachment.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
        VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    VkPipelineColorBlendStateCreateInfo blend{
        VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = 1;
    blend.pAttachments = &blendAttachment;
    const VkDynamicState dynamicStates[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamicStates;

    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &vertexInput;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = result.layout;
    info.renderPass = renderPass;
    info.subpass = 0;
    VK_CHECK(vkCreateGraphicsPipelines(context.device, VK_NULL_HANDLE, 1, &info, nullptr,
                                       &result.pipeline));
    return {};
}

}  // namespace

Expected<PatchPipeline> createPatchPipeline(const VulkanContext& context, VkRenderPass renderPass,
                                            VkDescriptorSetLayout detailLayout) {
    auto vertex = shaderModule(
        context, detailLayout ? "viewer_patches.vert/texture_detail" : "viewer_patches.vert");
    if (!vertex) return vertex.error();
    auto fragment = shaderModule(
        context, detailLayout ? "viewer_patches.frag/texture_detail" : "viewer_patches.frag");
    if (!fragment) {
        vkDestroyShaderModule(context.device, *vertex, nullptr);
        return fragment.error();
    }
    PatchPipeline result;
    auto made = makePatchPipeline(context, renderPass, *vertex, *fragment, detailLayout, result);
    vkDestroyShaderModule(context.device, *vertex, nullptr);
    vkDestroyShaderModule(context.device, *fragment, nullptr);
    if (!made) {
        destroyPatchPipeline(context, result);
        return made.error();
    }
    return result;
}

void destroyPatchPipeline(const VulkanContext& context, PatchPipeline& pipeline) {
    if (pipeline.pipeline) vkDestroyPipeline(context.device, pipeline.pipeline, nullptr);
    if (pipeline.layout) vkDestroyPipelineLayout(context.device, pipeline.layout, nullptr);
    pipeline = PatchPipeline{};
}

Expected<PatchBuffers> createPatchBuffers(const VulkanContext& context, const PatchMesh& mesh,
                                          int framesInFlight) {
    PatchBuffers buffers;
    buffers.vertexCount = uint32_t(3 * mesh.patchCount());
    const VkDeviceSize vertices = std::max<VkDeviceSize>(buffers.vertexCount, 3);
    auto positions =
        createHostBuffer(context, vertices * 4 * sizeof(float), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    if (!positions) return positions.error();
    buffers.positions = *positions;
    // w = 1 on both faces of a double-sided surface (PatchMesh::backPatch): the fragment shader
    // keeps only the face turned to the camera, so the coincident pair does not z-fight.
    std::vector<uint8_t> twoSided(mesh.patchCount(), 0);
    for (std::size_t p = 0; p < mesh.backPatch.size(); ++p) {
        if (mesh.backPatch[p] == kNoBackPatch) continue;
        twoSided[p] = 1;
        twoSided[mesh.backPatch[p]] = 1;
    }
    float* out = static_cast<float*>(buffers.positions.mapped);
    for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
        for (int corner = 0; corner < 3; ++corner) {
            const Vec3d& v = mesh.positions[mesh.patches[p][std::size_t(corner)]];
            for (int axis = 0; axis < 3; ++axis)
                *out++ = static_cast<float>(v[axis]);
            *out++ = float(twoSided[p]);
        }
    }
    for (int f = 0; f < framesInFlight; ++f) {
        auto values = createHostBuffer(context, vertices * 4 * sizeof(float),
                                       VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        if (!values) {
            destroyPatchBuffers(context, buffers);
            return values.error();
        }
        buffers.values.push_back(*values);
        std::memset(buffers.values.back().mapped, 0, vertices * 4 * sizeof(float));
        buffers.valueVersions.push_back(0);
    }
    return buffers;
}

void destroyPatchBuffers(const VulkanContext& context, PatchBuffers& buffers) {
    destroyHostBuffer(context, buffers.positions);
    for (HostBuffer& values : buffers.values)
        destroyHostBuffer(context, values);
    buffers = PatchBuffers{};
}

void recordPatches(VkCommandBuffer commandBuffer, const PatchPipeline& pipeline,
                   const PatchBuffers& buffers, int frame, const shared::ViewerPush& push,
                   VkRect2D area, const DetailTextures* detail) {
    if (buffers.vertexCount == 0) return;
    vkCmdBindPipeline(commandBuffer, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.pipeline);
    const VkViewport viewport{float(area.offset.x),
                              float(area.offset.y),
                              float(area.extent.width),
                              float(area.extent.height),
                              0,
                              1};
    const VkRect2D scissor = area;
    vkCmdSetViewport(commandBuffer, 0, 1, &viewport);
    vkCmdSetScissor(commandBuffer, 0, 1, &scissor);
    vkCmdPushConstants(commandBuffer, pipeline.layout,
                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(push),
                       &push);
    const VkBuffer vertexBuffers[3] = {buffers.positions.buffer,
                                       buffers.values[std::size_t(frame)].buffer,
                                       detail ? detail->vertices.buffer : VK_NULL_HANDLE};
    const VkDeviceSize offsets[3] = {0, 0, 0};
    vkCmdBindVertexBuffers(commandBuffer, 0, detail ? 3 : 2, vertexBuffers, offsets);
    if (!detail) {
        vkCmdDraw(commandBuffer, buffers.vertexCount, 1, 0, 0);
        return;
    }
    // One draw per run of patches sharing a texture; firstVertex keeps gl_VertexIndex the
    // patch-order index the picked patch is found by.
    for (const DetailRun& run : detail->runs) {
        vkCmdBindDescriptorSets(commandBuffer, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.layout, 0,
                                1, &detail->sets[run.texture], 0, nullptr);
        vkCmdDraw(commandBuffer, 3 * run.patchCount, 1, 3 * run.firstPatch, 0);
    }
}

}  // namespace daisy::viewer
