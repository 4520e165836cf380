#pragma once
// A Vulkan 1.2 context (STYLE.md rule 6): plain handles, created and destroyed by free functions,
// in three steps (niagara-style) so the headless compute backend and the viewer share the code:
// createInstance (with the window system's extensions when a surface is wanted) ->
// pickPhysicalDevice -> createDevice. The device is picked by --device (an index into the
// physical-device list or part of its name) or else by type: discrete, then integrated, then any
// (e.g. Mesa lavapipe). The compute backend requires Vulkan 1.2 with bufferDeviceAddress,
// scalarBlockLayout and shaderInt64 and a compute queue; the viewer a graphics queue that presents
// to its surface and VK_KHR_swapchain (the compute features are enabled whenever the device has
// them). Ray queries (VK_KHR_acceleration_structure, VK_KHR_ray_query and what they need) are
// enabled for compute wherever the device has them, and required by DeviceRequirements::rayQuery.
// Validation layers load when DAISY_VULKAN_VALIDATION=1 and they are installed.
#include <volk.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/expected.h"

namespace daisy {

struct VulkanContext {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;  // the requirements' queue (compute; graphics, present)
    uint32_t queueFamily = 0;
    bool computeFeatures = false;  // bufferDeviceAddress, scalarBlockLayout, shaderInt64 enabled
    // VK_KHR_acceleration_structure and VK_KHR_ray_query enabled (accelerationStructure,
    // rayQuery), with their VkPhysicalDeviceAccelerationStructurePropertiesKHR
    bool rayQuery = false;
    VkPhysicalDeviceAccelerationStructurePropertiesKHR accelerationProperties{};
    uint64_t maxBufferBytes = 0;  // largest allocation, bytes (maxMemoryAllocationSize)
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

// What a device must offer.
struct DeviceRequirements {
    bool compute = true;  // the compute backend's features and a compute queue
    bool graphics = false;  // a queue with graphics (with compute too when a family has both)
    VkSurfaceKHR presentSurface = VK_NULL_HANDLE;  // the queue presents to it; VK_KHR_swapchain
    bool rayQuery = false;  // acceleration structures and ray queries (--vulkan-rays query)
};

// True when `device` offers acceleration structures and ray queries to compute shaders, with
// buffer device addresses (what the vulkan backend's ray-query variant needs).
bool hasRayQuery(VkPhysicalDevice device);

// "discrete", "integrated", "virtual", "cpu" or "other".
const char* deviceTypeName(VkPhysicalDeviceType type);

// Every physical device with what it lacks; an error when there is no Vulkan loader, no driver
// or no device at all.
Expected<std::vector<VulkanDeviceInfo>> listVulkanDevices();

// Loads the Vulkan loader (once) and creates a Vulkan 1.2 instance with `extensions` (e.g. the
// surface extensions glfwGetRequiredInstanceExtensions names). Errors say what is missing.
Expected<VkInstance> createInstance(std::span<const char* const> extensions = {});

// The device `selector` names (see above; empty = by type) among those that meet
// `requirements`. Errors name the selector and list the devices found with what each lacks.
Expected<VkPhysicalDevice> pickPhysicalDevice(VkInstance instance, const std::string& selector,
                                              const DeviceRequirements& requirements);

// The logical device, its queue and command pool on `physicalDevice` (from pickPhysicalDevice
// with the same requirements). The context takes ownership of `instance`: destroyContext
// destroys both, also when this fails.
Expected<VulkanContext> createDevice(VkInstance instance, VkPhysicalDevice physicalDevice,
                                     const DeviceRequirements& requirements);

// createInstance + pickPhysicalDevice + createDevice for the headless compute backend, with ray
// queries required when `rayQuery` is set.
Expected<VulkanContext> createContext(const std::string& selector, bool rayQuery = false);
void destroyContext(VulkanContext& context);

// Records commands into a fresh primary command buffer with `record`, submits it and waits. An
// Error (VK_CHECK) when a call fails, e.g. the device is lost; `record` is not called when the
// command buffer cannot be begun.
template <typename Record>
Expected<void> submitAndWait(const VulkanContext& context, Record&& record);

// Implementation detail of submitAndWait.
Expected<VkCommandBuffer> beginOneShot(const VulkanContext& context);
Expected<void> endOneShot(const VulkanContext& context, VkCommandBuffer commandBuffer);

template <typename Record>
Expected<void> submitAndWait(const VulkanContext& context, Record&& record) {
    auto commandBuffer = beginOneShot(context);
    if (!commandBuffer) return commandBuffer.error();
    record(*commandBuffer);
    return endOneShot(context, *commandBuffer);
}

}  // namespace daisy
