#pragma once
// A headless Vulkan 1.2 compute context (STYLE.md rule 6): plain handles, created and destroyed
// by free functions. The device is picked by --device (an index into the physical-device list or
// part of its name) or else by type: discrete, then integrated, then any (e.g. Mesa lavapipe).
// Required: Vulkan 1.2 with bufferDeviceAddress, scalarBlockLayout and shaderInt64, and a queue
// with compute. Validation layers load when DAISY_VULKAN_VALIDATION=1 and they are installed.
#include <volk.h>

#include <cstdint>
#include <string>
#include <vector>

#include "core/expected.h"

namespace daisy {

struct VulkanContext {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    VkCommandPool commandPool = VK_NULL_HANDLE;  // resettable command buffers, queueFamily
    VkPhysicalDeviceProperties properties{};  // limits: maxStorageBufferRange, ...
    VkPhysicalDeviceMemoryProperties memory{};
};

// One physical device as --device sees it.
struct VulkanDeviceInfo {
    uint32_t index = 0;  // position in vkEnumeratePhysicalDevices order (--device N)
    std::string name;
    VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
    uint32_t apiVersion = 0;
    std::string unsupported;  // empty when usable; else what it lacks
};

// "discrete", "integrated", "virtual", "cpu" or "other".
const char* deviceTypeName(VkPhysicalDeviceType type);

// Every physical device with what it lacks; an error when there is no Vulkan loader, no driver
// or no device at all.
Expected<std::vector<VulkanDeviceInfo>> listVulkanDevices();

// Creates the context on the device `selector` names (see above; empty = by type). Errors name
// the selector and list the devices found.
Expected<VulkanContext> createContext(const std::string& selector);
void destroyContext(VulkanContext& context);

// Records commands into a fresh primary command buffer with `record`, submits it and waits.
template <typename Record>
void submitAndWait(const VulkanContext& context, Record&& record);

// Implementation detail of submitAndWait.
VkCommandBuffer beginOneShot(const VulkanContext& context);
void endOneShot(const VulkanContext& context, VkCommandBuffer commandBuffer);

template <typename Record>
void submitAndWait(const VulkanContext& context, Record&& record) {
    VkCommandBuffer commandBuffer = beginOneShot(context);
    record(commandBuffer);
    endOneShot(context, commandBuffer);
}

}  // namespace daisy
