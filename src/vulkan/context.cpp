#include "vulkan/context.h"

#include <cstdlib>
#include <cstring>
#include <iterator>
#include <mutex>
#include <vector>

#include "core/log.h"
#include "core/strings.h"
#include "vulkan/vk_check.h"

namespace daisy {
namespace {

const char* const kNoDevice =
    "no Vulkan device found (no GPU driver, and no software driver such as Mesa lavapipe: "
    "mesa-vulkan-drivers)";

// Loads the Vulkan loader once per process; false when none is installed.
bool loaderPresent() {
    static const bool present = volkInitialize() == VK_SUCCESS;
    return present;
}

bool validationRequested() {
    const char* value = std::getenv("DAISY_VULKAN_VALIDATION");
    return value && std::strcmp(value, "0") != 0 && value[0] != '\0';
}

bool layerPresent(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    for (const VkLayerProperties& layer : layers) {
        if (std::strcmp(layer.layerName, name) == 0) return true;
    }
    return false;
}

Expected<VkInstance> makeInstance(std::span<const char* const> extensions) {
    if (!loaderPresent()) {
        return Error{
            "no Vulkan loader (libvulkan.so.1) is installed; install a Vulkan driver "
            "(e.g. mesa-vulkan-drivers) or use --backend cpu"};
    }
    uint32_t loaderVersion = VK_API_VERSION_1_0;
    if (vkEnumerateInstanceVersion) vkEnumerateInstanceVersion(&loaderVersion);
    if (loaderVersion < VK_API_VERSION_1_2) {
        return Error{concat("the Vulkan loader offers version ",
                            VK_API_VERSION_MAJOR(loaderVersion), ".",
                            VK_API_VERSION_MINOR(loaderVersion), "; 1.2 is needed")};
    }
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "daisy";
    app.pEngineName = "DaisyRiot";
    app.apiVersion = VK_API_VERSION_1_2;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    const char* validationLayer = "VK_LAYER_KHRONOS_validation";
    if (validationRequested()) {
        if (layerPresent(validationLayer)) {
            info.enabledLayerCount = 1;
            info.ppEnabledLayerNames = &validationLayer;
        } else {
            logWarning(
                "DAISY_VULKAN_VALIDATION is set but VK_LAYER_KHRONOS_validation is not "
                "installed (Debian: vulkan-validationlayers); running without it");
        }
    }
    VkInstance instance = VK_NULL_HANDLE;
    const VkResult result = vkCreateInstance(&info, nullptr, &instance);
    if (result != VK_SUCCESS) {
        if (result == VK_ERROR_INCOMPATIBLE_DRIVER) {
            return Error{
                "no Vulkan driver found (a GPU vendor's, or Mesa's lavapipe CPU driver "
                "from mesa-vulkan-drivers); install one or use --backend cpu"};
        }
        return Error{concat("cannot create a Vulkan 1.2 instance (", vkResultName(result), ")")};
    }
    // Instance-level loading only: device functions go through the loader's dispatch, which is
    // right for every device of every context alive in the process. volk keeps one table for
    // the process; what it takes from any instance are the loader's trampolines, valid for every
    // instance, except that an extension's functions are null when taken from an instance that
    // did not enable it. So the table is loaded by the first instance and again only by one
    // that enables the surface extension when the loaded one did not: a headless instance made
    // later (the backend's probe while a window is open) must not null the window's
    // vkDestroySurfaceKHR.
    static std::mutex loadMutex;
    static bool loaded = false, loadedWithSurface = false;
    bool withSurface = false;
    for (const char* name : extensions)
        withSurface = withSurface || std::strcmp(name, VK_KHR_SURFACE_EXTENSION_NAME) == 0;
    const std::lock_guard lock(loadMutex);
    if (!loaded || (withSurface && !loadedWithSurface)) {
        volkLoadInstance(instance);
        loaded = true;
        loadedWithSurface = withSurface;
    }
    return instance;
}

bool hasDeviceExtension(VkPhysicalDevice device, const char* name) {
    uint32_t count = 0;
    vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> extensions(count);
    vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data());
    for (const VkExtensionProperties& extension : extensions) {
        if (std::strcmp(extension.extensionName, name) == 0) return true;
    }
    return false;
}

// The device extensions ray queries need: the two named ones, and deferred host operations,
// which VK_KHR_acceleration_structure requires.
constexpr const char* kRayQueryExtensions[] = {VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
                                               VK_KHR_RAY_QUERY_EXTENSION_NAME,
                                               VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME};

// True when `device` has the compute backend's features.
bool hasComputeFeatures(VkPhysicalDevice device) {
    VkPhysicalDeviceVulkan12Features features12{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features.pNext = &features12;
    vkGetPhysicalDeviceFeatures2(device, &features);
    return features12.bufferDeviceAddress && features12.scalarBlockLayout &&
        features.features.shaderInt64;
}

// What `device` lacks for `requirements`, or "" and the queue family to use.
std::string checkDevice(VkPhysicalDevice device, const DeviceRequirements& requirements,
                        uint32_t& queueFamily) {
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(device, &properties);
    if (properties.apiVersion < VK_API_VERSION_1_2) return "Vulkan 1.2";
    VkPhysicalDeviceVulkan12Features features12{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features.pNext = &features12;
    vkGetPhysicalDeviceFeatures2(device, &features);
    std::string missing;
    const auto need = [&](bool present, const char* name) {
        if (!present) missing += missing.empty() ? name : concat(", ", name);
    };
    if (requirements.compute) {
        need(features12.bufferDeviceAddress, "bufferDeviceAddress");
        need(features12.scalarBlockLayout, "scalarBlockLayout");
        need(features.features.shaderInt64, "shaderInt64");
    }
    if (requirements.presentSurface) {
        need(hasDeviceExtension(device, VK_KHR_SWAPCHAIN_EXTENSION_NAME), "VK_KHR_swapchain");
    }
    if (requirements.rayQuery) {
        bool extensions = true;
        for (const char* extension : kRayQueryExtensions) {
            const bool present = hasDeviceExtension(device, extension);
            need(present, extension);
            extensions = extensions && present;
        }
        if (extensions)
            need(hasRayQuery(device), "the accelerationStructure and rayQuery features");
    }
    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &familyCount, families.data());
    bool found = false;
    VkQueueFlags needed = 0;
    if (requirements.compute) needed |= VK_QUEUE_COMPUTE_BIT;
    if (requirements.graphics) needed |= VK_QUEUE_GRAPHICS_BIT;
    // A family with compute as well is preferred, so one queue can serve both uses.
    for (const VkQueueFlags flags : {needed | VK_QUEUE_COMPUTE_BIT, needed}) {
        for (uint32_t f = 0; f < familyCount && !found; ++f) {
            if ((families[f].queueFlags & flags) != flags) continue;
            if (requirements.presentSurface) {
                VkBool32 presents = VK_FALSE;
                vkGetPhysicalDeviceSurfaceSupportKHR(device, f, requirements.presentSurface,
                                                     &presents);
                if (!presents) continue;
            }
            queueFamily = f;
            found = true;
        }
    }
    need(found,
         requirements.presentSurface ? "a graphics queue that presents to the window"
             : requirements.graphics ? "a graphics and compute queue"
                                     : "a compute queue");
    return missing;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
    uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(instance, &count, devices.data());
    devices.resize(count);
    return devices;
}

std::vector<VulkanDeviceInfo> describe(const std::vector<VkPhysicalDevice>& devices,
                                       const DeviceRequirements& requirements) {
    std::vector<VulkanDeviceInfo> infos;
    for (uint32_t k = 0; k < devices.size(); ++k) {
        VkPhysicalDeviceProperties properties;
        vkGetPhysicalDeviceProperties(devices[k], &properties);
        VulkanDeviceInfo info;
        info.index = k;
        info.name = properties.deviceName;
        info.type = properties.deviceType;
        info.apiVersion = properties.apiVersion;
        uint32_t family = 0;
        info.unsupported = checkDevice(devices[k], requirements, family);
        infos.push_back(std::move(info));
    }
    return infos;
}

std::string deviceList(const std::vector<VulkanDeviceInfo>& infos) {
    std::string text;
    for (const VulkanDeviceInfo& info : infos) {
        text += concat(text.empty() ? "" : "; ", info.index, " '", info.name, "' (",
                       deviceTypeName(info.type),
                       info.unsupported.empty() ? "" : concat(", lacks ", info.unsupported), ")");
    }
    return text;
}

int typeRank(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return 3;
        default:
            return 4;
    }
}

bool isIndex(const std::string& text) {
    if (text.empty() || text.size() > 9) return false;
    for (char c : text) {
        if (c < '0' || c > '9') return false;
    }
    return true;
}

std::string lowercase(std::string text) {
    for (char& c : text) {
        if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    }
    return text;
}

// The chosen index into `infos`, or an error naming the selector.
Expected<uint32_t> selectDevice(const std::vector<VulkanDeviceInfo>& infos,
                                const std::string& selector, const char* purpose) {
    const std::string found = concat(" (found: ", deviceList(infos), ")");
    if (selector.empty()) {
        int best = -1;
        for (const VulkanDeviceInfo& info : infos) {
            if (!info.unsupported.empty()) continue;
            if (best < 0 || typeRank(info.type) < typeRank(infos[best].type))
                best = int(info.index);
        }
        if (best < 0) return Error{concat("no Vulkan device supports ", purpose, found)};
        return uint32_t(best);
    }
    int chosen = -1;
    if (isIndex(selector)) {
        const unsigned long index = std::strtoul(selector.c_str(), nullptr, 10);
        if (index >= infos.size()) {
            return Error{
                concat("--device ", selector, ": there is no Vulkan device ", selector, found)};
        }
        chosen = int(index);
    } else {
        for (const VulkanDeviceInfo& info : infos) {
            if (lowercase(info.name).find(lowercase(selector)) == std::string::npos) continue;
            if (chosen < 0) chosen = int(info.index);  // a match, maybe unsupported
            if (info.unsupported.empty()) {
                chosen = int(info.index);
                break;
            }
        }
        if (chosen < 0) {
            return Error{concat("--device ", selector, ": no Vulkan device's name contains '",
                                selector, "'", found)};
        }
    }
    if (!infos[chosen].unsupported.empty()) {
        return Error{concat("--device ", selector, ": Vulkan device '", infos[chosen].name,
                            "' lacks ", infos[chosen].unsupported)};
    }
    return uint32_t(chosen);
}

}  // namespace

bool hasRayQuery(VkPhysicalDevice device) {
    for (const char* extension : kRayQueryExtensions) {
        if (!hasDeviceExtension(device, extension)) return false;
    }
    VkPhysicalDeviceRayQueryFeaturesKHR rayQuery{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
    VkPhysicalDeviceAccelerationStructureFeaturesKHR acceleration{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
    acceleration.pNext = &rayQuery;
    VkPhysicalDeviceVulkan12Features features12{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    features12.pNext = &acceleration;
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features.pNext = &features12;
    vkGetPhysicalDeviceFeatures2(device, &features);
    return features12.bufferDeviceAddress && acceleration.accelerationStructure &&
        rayQuery.rayQuery;
}

const char* deviceTypeName(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return "discrete";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return "integrated";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return "virtual";
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return "cpu";
        default:
            return "other";
    }
}

Expected<VkInstance> createInstance(std::span<const char* const> extensions) {
    return makeInstance(extensions);
}

Expected<std::vector<VulkanDeviceInfo>> listVulkanDevices() {
    auto instance = createInstance();
    if (!instance) return instance.error();
    std::vector<VulkanDeviceInfo> infos = describe(physicalDevices(*instance), {});
    vkDestroyInstance(*instance, nullptr);
    if (infos.empty()) return Error{kNoDevice};
    return infos;
}

Expected<VkPhysicalDevice> pickPhysicalDevice(VkInstance instance, const std::string& selector,
                                              const DeviceRequirements& requirements) {
    const std::vector<VkPhysicalDevice> devices = physicalDevices(instance);
    const std::vector<VulkanDeviceInfo> infos = describe(devices, requirements);
    if (infos.empty()) return Error{kNoDevice};
    auto chosen =
        selectDevice(infos, selector,
                     requirements.presentSurface ? "the viewer (graphics and present)"
                         : requirements.rayQuery
                         ? "the compute backend with ray queries, as --vulkan-rays query asks"
                         : "the compute backend");
    if (!chosen) return chosen.error();
    return devices[*chosen];
}

Expected<VulkanContext> createDevice(VkInstance instance, VkPhysicalDevice physicalDevice,
                                     const DeviceRequirements& requirements) {
    VulkanContext context;
    context.instance = instance;
    context.physicalDevice = physicalDevice;
    checkDevice(context.physicalDevice, requirements, context.queueFamily);
    vkGetPhysicalDeviceProperties(context.physicalDevice, &context.properties);
    vkGetPhysicalDeviceMemoryProperties(context.physicalDevice, &context.memory);
    context.computeFeatures = hasComputeFeatures(context.physicalDevice);
    context.rayQuery =
        requirements.compute && context.computeFeatures && hasRayQuery(context.physicalDevice);
    // The instance is Vulkan 1.2, so maxMemoryAllocationSize (1.1) bounds one buffer; 1.3's
    // maxBufferSize is not visible to it.
    VkPhysicalDeviceMaintenance3Properties maintenance3{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    context.accelerationProperties.sType =
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR;
    if (context.rayQuery) maintenance3.pNext = &context.accelerationProperties;
    VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties2.pNext = &maintenance3;
    vkGetPhysicalDeviceProperties2(context.physicalDevice, &properties2);
    context.accelerationProperties.pNext = nullptr;
    context.maxBufferBytes = maintenance3.maxMemoryAllocationSize;

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = context.queueFamily;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;
    VkPhysicalDeviceRayQueryFeaturesKHR rayQuery{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
    rayQuery.rayQuery = VK_TRUE;
    VkPhysicalDeviceAccelerationStructureFeaturesKHR acceleration{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
    acceleration.pNext = &rayQuery;
    acceleration.accelerationStructure = VK_TRUE;
    VkPhysicalDeviceVulkan12Features features12{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    features12.bufferDeviceAddress = context.computeFeatures;
    features12.scalarBlockLayout = context.computeFeatures;
    if (context.rayQuery) features12.pNext = &acceleration;
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features.pNext = &features12;
    features.features.shaderInt64 = context.computeFeatures;
    VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    deviceInfo.pNext = &features;
    deviceInfo.queueCreateInfoCount = 1;
    deviceInfo.pQueueCreateInfos = &queueInfo;
    std::vector<const char*> extensions;
    if (requirements.presentSurface) extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    if (context.rayQuery) {
        extensions.insert(extensions.end(), std::begin(kRayQueryExtensions),
                          std::end(kRayQueryExtensions));
    }
    deviceInfo.enabledExtensionCount = uint32_t(extensions.size());
    deviceInfo.ppEnabledExtensionNames = extensions.data();
    const VkResult result =
        vkCreateDevice(context.physicalDevice, &deviceInfo, nullptr, &context.device);
    if (result != VK_SUCCESS) {
        const std::string name = context.properties.deviceName;
        destroyContext(context);
        return Error{
            concat("cannot create a logical device on '", name, "' (", vkResultName(result), ")")};
    }
    vkGetDeviceQueue(context.device, context.queueFamily, 0, &context.queue);
    auto pool = [&]() -> Expected<void> {
        VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        poolInfo.queueFamilyIndex = context.queueFamily;
        VK_CHECK(vkCreateCommandPool(context.device, &poolInfo, nullptr, &context.commandPool));
        return {};
    }();
    if (!pool) {
        destroyContext(context);
        return pool.error();
    }
    return context;
}

Expected<VulkanContext> createContext(const std::string& selector, bool rayQuery) {
    auto instance = createInstance();
    if (!instance) return instance.error();
    DeviceRequirements requirements;
    requirements.rayQuery = rayQuery;
    auto physicalDevice = pickPhysicalDevice(*instance, selector, requirements);
    if (!physicalDevice) {
        vkDestroyInstance(*instance, nullptr);
        return physicalDevice.error();
    }
    return createDevice(*instance, *physicalDevice, requirements);
}

void destroyContext(VulkanContext& context) {
    if (context.device) {
        vkDeviceWaitIdle(context.device);
        if (context.commandPool) vkDestroyCommandPool(context.device, context.commandPool, nullptr);
        vkDestroyDevice(context.device, nullptr);
    }
    if (context.instance) vkDestroyInstance(context.instance, nullptr);
    context = VulkanContext{};
}

Expected<VkCommandBuffer> beginOneShot(const VulkanContext& context) {
    VkCommandBufferAllocateInfo allocateInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    allocateInfo.commandPool = context.commandPool;
    allocateInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    allocateInfo.commandBufferCount = 1;
    VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateCommandBuffers(context.device, &allocateInfo, &commandBuffer));
    auto begun = [&]() -> Expected<void> {
        VkCommandBufferBeginInfo beginInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        beginInfo.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        VK_CHECK(vkBeginCommandBuffer(commandBuffer, &beginInfo));
        return {};
    }();
    if (!begun) {
        vkFreeCommandBuffers(context.device, context.commandPool, 1, &commandBuffer);
        return begun.error();
    }
    return commandBuffer;
}

Expected<void> endOneShot(const VulkanContext& context, VkCommandBuffer commandBuffer) {
    VkFence fence = VK_NULL_HANDLE;
    const auto release = [&] {
        if (fence) vkDestroyFence(context.device, fence, nullptr);
        vkFreeCommandBuffers(context.device, context.commandPool, 1, &commandBuffer);
    };
    auto submitted = [&]() -> Expected<void> {
        VK_CHECK(vkEndCommandBuffer(commandBuffer));
        VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VK_CHECK(vkCreateFence(context.device, &fenceInfo, nullptr, &fence));
        VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &commandBuffer;
        VK_CHECK(vkQueueSubmit(context.queue, 1, &submit, fence));
        return {};
    }();
    if (!submitted) {
        release();  // nothing was queued
        return submitted.error();
    }
    // A failed wait (a lost device) leaves the fence and the command buffer, which may still be
    // pending, to destroyContext.
    VK_CHECK(vkWaitForFences(context.device, 1, &fence, VK_TRUE, UINT64_MAX));
    release();
    return {};
}

}  // namespace daisy
