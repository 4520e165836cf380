#pragma once
// The raster pipeline of the patches: three vertices per patch in patch order
// (no index buffer: corners of neighbouring patches carry different values across creases and
// material boundaries), positions in one buffer, display values in one buffer per frame in
// flight, depth tested (reverse-Z), no culling (the radiosity solution is two-sided only where
// the scene is, and a back face seen from inside an open box must still hide what is behind it).
// Shaders: shaders/viewer_patches.{vert,frag}.glsl; push constants: shared/viewer_types.h. With
// texture detail (viewer/detail_textures.h) the shaders' texture_detail variant reads a third
// vertex buffer and one texture per run of patches; without it the pipeline is the plain one.
#include <volk.h>

#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "shared/viewer_types.h"
#include "viewer/detail_textures.h"
#include "viewer/gpu_resources.h"
#include "vulkan/context.h"

namespace daisy::viewer {

struct PatchPipeline {
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
};

// The plain pipeline, or with `detailLayout` (DetailTextures::setLayout) the texture detail's. An
// Error (VK_CHECK) when the driver fails to make it; nothing is left allocated then.
Expected<PatchPipeline> createPatchPipeline(const VulkanContext& context, VkRenderPass renderPass,
                                            VkDescriptorSetLayout detailLayout = VK_NULL_HANDLE);
void destroyPatchPipeline(const VulkanContext& context, PatchPipeline& pipeline);

struct PatchBuffers {
    HostBuffer positions;  // vertexCount x 4 floats: x, y, z (scene units), double-sided flag
    std::vector<HostBuffer> values;  // per frame in flight: vertexCount x 4 floats
    std::vector<uint64_t> valueVersions;  // what each values buffer holds (0 = nothing)
    uint32_t vertexCount = 0;  // 3 x patches
};

// The positions of `mesh` and zeroed values. An Error (VK_CHECK) when a buffer cannot be made;
// nothing is left allocated then.
Expected<PatchBuffers> createPatchBuffers(const VulkanContext& context, const PatchMesh& mesh,
                                          int framesInFlight);
void destroyPatchBuffers(const VulkanContext& context, PatchBuffers& buffers);

// Draws the patches with `values` buffer `frame` into the render pass begun on `commandBuffer`
// (viewport and scissor set to `area`, the window right of the docked panel); `detail` is given
// exactly when `pipeline` was made with its layout.
void recordPatches(VkCommandBuffer commandBuffer, const PatchPipeline& pipeline,
                   const PatchBuffers& buffers, int frame, const shared::ViewerPush& push,
                   VkRect2D area, const DetailTextures* detail = nullptr);

}  // namespace daisy::viewer
