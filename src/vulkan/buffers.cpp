#include "vulkan/buffers.h"

#include <cstring>

#include "core/check.h"
#include "vulkan/vk_check.h"

namespace daisy {
namespace {

// The first memory type allowed by `typeBits` with every flag of `required`; -1 when none.
int findMemoryType(const VulkanContext& context, uint32_t typeBits,
                   VkMemoryPropertyFlags required) {
    for (uint32_t t = 0; t < context.memory.memoryTypeCount; ++t) {
        if ((typeBits & (1u << t)) &&
            (context.memory.memoryTypes[t].propertyFlags & required) == required) {
            return int(t);
        }
    }
    return -1;
}

// Creates result's buffer, memory and mapping for createBuffer; what it made stays in `result`
// when it fails, for the caller to destroy.
Expected<void> makeBuffer(const VulkanContext& context, VkBufferUsageFlags extraUsage,
                          bool hostVisible, VulkanBuffer& result) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = result.bytes;
    info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
        VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | extraUsage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(context.device, &info, nullptr, &result.buffer));
    VkMemoryRequirements requirements;
    vkGetBufferMemoryRequirements(context.device, result.buffer, &requirements);

    const VkMemoryPropertyFlags hostFlags =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    int type = -1;
    if (hostVisible) {
        type = findMemoryType(context, requirements.memoryTypeBits, hostFlags);
    } else {
        type = findMemoryType(context, requirements.memoryTypeBits,
                              VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | hostFlags);
        if (type < 0) {
            type = findMemoryType(context, requirements.memoryTypeBits,
                                  VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        }
    }
    if (type < 0) type = findMemoryType(context, requirements.memoryTypeBits, 0);
    DAISY_CHECK(type >= 0);

    VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateInfo allocateInfo{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    allocateInfo.pNext = &flags;
    allocateInfo.allocationSize = requirements.size;
    allocateInfo.memoryTypeIndex = uint32_t(type);
    VK_CHECK(vkAllocateMemory(context.device, &allocateInfo, nullptr, &result.memory));
    VK_CHECK(vkBindBufferMemory(context.device, result.buffer, result.memory, 0));
    if ((context.memory.memoryTypes[type].propertyFlags & hostFlags) == hostFlags) {
        VK_CHECK(vkMapMemory(context.device, result.memory, 0, VK_WHOLE_SIZE, 0, &result.mapped));
    }
    VkBufferDeviceAddressInfo addressInfo{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    addressInfo.buffer = result.buffer;
    result.address = vkGetBufferDeviceAddress(context.device, &addressInfo);
    return {};
}

}  // namespace

Expected<VulkanBuffer> createBuffer(const VulkanContext& context, VkDeviceSize bytes,
                                    VkBufferUsageFlags extraUsage, bool hostVisible) {
    DAISY_CHECK_OP(bytes, >, 0u);
    VulkanBuffer result;
    result.bytes = bytes;
    if (auto made = makeBuffer(context, extraUsage, hostVisible, result); !made) {
        destroyBuffer(context, result);
        return made.error();
    }
    return result;
}

void destroyBuffer(const VulkanContext& context, VulkanBuffer& buffer) {
    if (buffer.buffer) vkDestroyBuffer(context.device, buffer.buffer, nullptr);
    if (buffer.memory) vkFreeMemory(context.device, buffer.memory, nullptr);  // unmaps too
    buffer = VulkanBuffer{};
}

Expected<void> upload(const VulkanContext& context, const VulkanBuffer& buffer, const void* data,
                      std::size_t bytes, VkDeviceSize offset) {
    DAISY_CHECK_OP(offset + bytes, <=, buffer.bytes);
    if (bytes == 0) return {};
    if (buffer.mapped) {
        std::memcpy(static_cast<char*>(buffer.mapped) + offset, data, bytes);
        return {};
    }
    auto staging = createBuffer(context, bytes, 0, /*hostVisible=*/true);
    if (!staging) return staging.error();
    std::memcpy(staging->mapped, data, bytes);
    auto copied = submitAndWait(context, [&](VkCommandBuffer commands) {
        const VkBufferCopy region{0, offset, bytes};
        vkCmdCopyBuffer(commands, staging->buffer, buffer.buffer, 1, &region);
    });
    destroyBuffer(context, *staging);
    return copied;
}

Expected<void> download(const VulkanContext& context, const VulkanBuffer& buffer, void* data,
                        std::size_t bytes, VkDeviceSize offset) {
    DAISY_CHECK_OP(offset + bytes, <=, buffer.bytes);
    if (bytes == 0) return {};
    if (buffer.mapped) {
        std::memcpy(data, static_cast<const char*>(buffer.mapped) + offset, bytes);
        return {};
    }
    auto staging = createBuffer(context, bytes, 0, /*hostVisible=*/true);
    if (!staging) return staging.error();
    auto copied = submitAndWait(context, [&](VkCommandBuffer commands) {
        const VkBufferCopy region{offset, 0, bytes};
        vkCmdCopyBuffer(commands, buffer.buffer, staging->buffer, 1, &region);
    });
    if (copied) std::memcpy(data, staging->mapped, bytes);
    destroyBuffer(context, *staging);
    return copied;
}

}  // namespace daisy
