#pragma once
// Storage buffers with device addresses (STYLE.md rule 6: a handful of large buffers, no
// descriptor sets). Memory is device-local; when that memory is also host-visible (integrated
// GPUs, resizable BAR, lavapipe) the buffer stays mapped and upload/download are memcpy, else they
// go through a temporary staging buffer and a copy on the queue.
#include <volk.h>

#include <cstddef>
#include <cstdint>

#include "core/expected.h"
#include "vulkan/context.h"

namespace daisy {

struct VulkanBuffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize bytes = 0;
    VkDeviceAddress address = 0;  // for GLSL buffer_reference (GL_EXT_buffer_reference)
    void* mapped = nullptr;  // host pointer when the memory is host-visible and coherent
};

// A storage buffer of `bytes` (> 0) with a device address; `extraUsage` adds usage bits. An
// Error (VK_CHECK) when the device cannot make it, e.g. out of device memory; nothing is left
// allocated then.
Expected<VulkanBuffer> createBuffer(const VulkanContext& context, VkDeviceSize bytes,
                                    VkBufferUsageFlags extraUsage = 0, bool hostVisible = false);
void destroyBuffer(const VulkanContext& context, VulkanBuffer& buffer);

// Copies `bytes` from host `data` into the buffer at byte `offset` (in range), and back. Errors
// only on the staging path (a staging buffer or the copy's submission failed).
Expected<void> upload(const VulkanContext& context, const VulkanBuffer& buffer, const void* data,
                      std::size_t bytes, VkDeviceSize offset = 0);
Expected<void> download(const VulkanContext& context, const VulkanBuffer& buffer, void* data,
                        std::size_t bytes, VkDeviceSize offset = 0);

}  // namespace daisy
