#pragma once
// The GPU side of the viewer's texture detail (viewer/detail_vertices.h): the per-vertex detail
// in a vertex buffer, each texture as a sampled image (VK_FORMAT_R8G8B8A8_SRGB: the 8-bit sRGB
// values the loader decoded, so the texture unit's sRGB decode, done before filtering, gives back
// the loader's linear texels exactly) with a sampler of its glTF wrap and filter (one level, no
// mipmaps: `daisy render` samples the full image, bilinear or nearest, at every scale), and one
// descriptor set per texture (set 0, binding DAISY_VIEWER_DETAIL_BINDING).
#include <volk.h>

#include <vector>

#include "core/expected.h"
#include "scene/scene.h"
#include "viewer/detail_vertices.h"
#include "viewer/gpu_resources.h"
#include "vulkan/context.h"

namespace daisy::viewer {

struct DetailTextures {
    HostBuffer vertices;  // DetailVertices::vertices
    std::vector<DeviceImage> images;  // one per scene image used, and the white texel
    std::vector<VkSampler> samplers;  // per DetailVertices::textures entry
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    std::vector<VkDescriptorSet> sets;  // per DetailVertices::textures entry
    std::vector<DetailRun> runs;
};

// Uploads `detail` (not empty) and the textures it reads from `scene`, waiting for the copies. An
// Error (VK_CHECK) when the device cannot make or fill them; nothing is left allocated then.
Expected<DetailTextures> createDetailTextures(const VulkanContext& context, const Scene& scene,
                                              const DetailVertices& detail);
void destroyDetailTextures(const VulkanContext& context, DetailTextures& textures);

}  // namespace daisy::viewer
