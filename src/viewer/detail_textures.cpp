#include "viewer/detail_textures.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/check.h"
#include "core/strings.h"
#include "shared/viewer_types.h"
#include "spectral/color.h"
#include "vulkan/vk_check.h"

namespace daisy::viewer {
namespace {

constexpr VkFormat kTextureFormat = VK_FORMAT_R8G8B8A8_SRGB;

VkSamplerAddressMode addressMode(TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::ClampToEdge:
            return VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
        case TextureWrap::MirroredRepeat:
            return VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT;
        default:
            return VK_SAMPLER_ADDRESS_MODE_REPEAT;
    }
}

// The RGBA8 sRGB texels of `image` (linear floats from the loader's sRGB decode, encoded back:
// each comes out as the byte it was read from).
void encodeTexels(const TextureImage& image, uint8_t* out) {
    const std::size_t texels = std::size_t(image.width) * std::size_t(image.height);
    for (std::size_t p = 0; p < texels; ++p) {
        for (std::size_t c = 0; c < 3; ++c) {
            const double encoded = srgbEncode(std::clamp(double(image.rgb[p * 3 + c]), 0.0, 1.0));
            out[p * 4 + c] = uint8_t(std::lround(encoded * 255));
        }
        out[p * 4 + 3] = 255;
    }
}

// Records the layout change of `image` for a copy into it, or from that to sampling.
void imageBarrier(VkCommandBuffer commandBuffer, VkImage image, bool toShader) {
    VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    barrier.srcAccessMask = toShader ? VK_ACCESS_TRANSFER_WRITE_BIT : 0;
    barrier.dstAccessMask = toShader ? VK_ACCESS_SHADER_READ_BIT : VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.oldLayout = toShader ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED;
    barrier.newLayout =
        toShader ? VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = image;
    barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(
        commandBuffer,
        toShader ? VK_PIPELINE_STAGE_TRANSFER_BIT : VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
        toShader ? VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT : VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
        nullptr, 0, nullptr, 1, &barrier);
}

// One image of createDetailTextures, made and filled through a staging buffer of its own (so the
// upload's peak is one image, however many the scene has), into `result.images`.
Expected<void> uploadImage(const VulkanContext& context, const TextureImage& image,
                           DetailTextures& result) {
    DAISY_CHECK(image.width >= 1 && image.height >= 1);
    const uint32_t limit = context.properties.limits.maxImageDimension2D;
    if (uint32_t(image.width) > limit || uint32_t(image.height) > limit) {
        return Error{concat("texture ", image.name, " is ", image.width, " x ", image.height,
                            ", over the ", limit, " texels a side that device '",
                            context.properties.deviceName, "' samples")};
    }
    const VkDeviceSize bytes = VkDeviceSize(image.width) * VkDeviceSize(image.height) * 4;
    auto made = createDeviceImage(
        context, uint32_t(image.width), uint32_t(image.height), kTextureFormat,
        VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, VK_IMAGE_ASPECT_COLOR_BIT);
    if (!made) return made.error();
    result.images.push_back(*made);
    auto staging = createHostBuffer(context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
    if (!staging) return staging.error();
    encodeTexels(image, static_cast<uint8_t*>(staging->mapped));
    const VkImage target = made->image;
    auto copied = submitAndWait(context, [&](VkCommandBuffer commandBuffer) {
        imageBarrier(commandBuffer, target, false);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {uint32_t(image.width), uint32_t(image.height), 1};
        vkCmdCopyBufferToImage(commandBuffer, staging->buffer, target,
                               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        imageBarrier(commandBuffer, target, true);
    });
    destroyHostBuffer(context, *staging);
    return copied;
}

// The images of createDetailTextures: one per scene image the textures read, plus the white
// texel; `imageOf[k]` is texture k's image.
Expected<void> uploadImages(const VulkanContext& context, const Scene& scene,
                            const DetailVertices& detail, DetailTextures& result,
                            std::vector<std::size_t>& imageOf) {
    std::vector<int> sources;  // scene image per uploaded image; -1 = the white texel
    for (const DetailTexture& texture : detail.textures) {
        const auto found = std::find(sources.begin(), sources.end(), texture.image);
        imageOf.push_back(std::size_t(found - sources.begin()));
        if (found == sources.end()) sources.push_back(texture.image);
    }
    static const TextureImage kWhite{"(white texel)", 1, 1, {1, 1, 1}};
    for (int source : sources) {
        auto uploaded =
            uploadImage(context, source < 0 ? kWhite : scene.textures[std::size_t(source)], result);
        if (!uploaded) return uploaded;
    }
    return {};
}

// What createDetailTextures makes, into `result`; what it made stays there when it fails, for
// the caller to destroy.
Expected<void> makeDetailTextures(const VulkanContext& context, const Scene& scene,
                                  const DetailVertices& detail, DetailTextures& result) {
    const VkDeviceSize vertexBytes = detail.vertices.size() * sizeof(float);
    auto vertices = createHostBuffer(context, vertexBytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    if (!vertices) return vertices.error();
    result.vertices = *vertices;
    std::memcpy(result.vertices.mapped, detail.vertices.data(), vertexBytes);
    std::vector<std::size_t> imageOf;
    if (auto uploaded = uploadImages(context, scene, detail, result, imageOf); !uploaded)
        return uploaded;

    for (const DetailTexture& texture : detail.textures) {
        VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
        info.magFilter = texture.nearest ? VK_FILTER_NEAREST : VK_FILTER_LINEAR;
        info.minFilter = info.magFilter;
        info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
        info.addressModeU = addressMode(texture.wrapS);
        info.addressModeV = addressMode(texture.wrapT);
        info.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
        info.maxLod = 0;
        VkSampler sampler = VK_NULL_HANDLE;
        VK_CHECK(vkCreateSampler(context.device, &info, nullptr, &sampler));
        result.samplers.push_back(sampler);
    }

    VkDescriptorSetLayoutBinding binding{};
    binding.binding = DAISY_VIEWER_DETAIL_BINDING;
    binding.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    binding.descriptorCount = 1;
    binding.stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT;
    VkDescriptorSetLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    layoutInfo.bindingCount = 1;
    layoutInfo.pBindings = &binding;
    VK_CHECK(vkCreateDescriptorSetLayout(context.device, &layoutInfo, nullptr, &result.setLayout));
    const uint32_t count = uint32_t(detail.textures.size());
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, count};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = count;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &size;
    VK_CHECK(vkCreateDescriptorPool(context.device, &poolInfo, nullptr, &result.pool));
    const std::vector<VkDescriptorSetLayout> layouts(count, result.setLayout);
    VkDescriptorSetAllocateInfo allocateInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    allocateInfo.descriptorPool = result.pool;
    allocateInfo.descriptorSetCount = count;
    allocateInfo.pSetLayouts = layouts.data();
    result.sets.resize(count);
    VK_CHECK(vkAllocateDescriptorSets(context.device, &allocateInfo, result.sets.data()));
    for (uint32_t k = 0; k < count; ++k) {
        const VkDescriptorImageInfo image{result.samplers[k], result.images[imageOf[k]].view,
                                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        write.dstSet = result.sets[k];
        write.dstBinding = DAISY_VIEWER_DETAIL_BINDING;
        write.descriptorCount = 1;
        write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        write.pImageInfo = &image;
        vkUpdateDescriptorSets(context.device, 1, &write, 0, nullptr);
    }
    result.runs = detail.runs;
    return {};
}

}  // namespace

Expected<DetailTextures> createDetailTextures(const VulkanContext& context, const Scene& scene,
                                              const DetailVertices& detail) {
    DAISY_CHECK(!detail.empty() && !detail.textures.empty());
    DetailTextures result;
    if (auto made = makeDetailTextures(context, scene, detail, result); !made) {
        destroyDetailTextures(context, result);
        return made.error();
    }
    return result;
}

void destroyDetailTextures(const VulkanContext& context, DetailTextures& textures) {
    destroyHostBuffer(context, textures.vertices);
    for (DeviceImage& image : textures.images)
        destroyDeviceImage(context, image);
    for (VkSampler sampler : textures.samplers)
        vkDestroySampler(context.device, sampler, nullptr);
    // The sets go with their pool.
    if (textures.pool) vkDestroyDescriptorPool(context.device, textures.pool, nullptr);
    if (textures.setLayout)
        vkDestroyDescriptorSetLayout(context.device, textures.setLayout, nullptr);
    textures = DetailTextures{};
}

}  // namespace daisy::viewer
