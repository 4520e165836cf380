#include "vulkan/vk_check.h"

#include <cstdio>
#include <cstring>

#include "core/strings.h"

namespace daisy {

const char* vkResultName(VkResult result) {
    switch (result) {
#define DAISY_VK_RESULT(name) \
    case name:                \
        return #name;
        DAISY_VK_RESULT(VK_SUCCESS)
        DAISY_VK_RESULT(VK_NOT_READY)
        DAISY_VK_RESULT(VK_TIMEOUT)
        DAISY_VK_RESULT(VK_EVENT_SET)
        DAISY_VK_RESULT(VK_EVENT_RESET)
        DAISY_VK_RESULT(VK_INCOMPLETE)
        DAISY_VK_RESULT(VK_ERROR_OUT_OF_HOST_MEMORY)
        DAISY_VK_RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        DAISY_VK_RESULT(VK_ERROR_INITIALIZATION_FAILED)
        DAISY_VK_RESULT(VK_ERROR_DEVICE_LOST)
        DAISY_VK_RESULT(VK_ERROR_MEMORY_MAP_FAILED)
        DAISY_VK_RESULT(VK_ERROR_LAYER_NOT_PRESENT)
        DAISY_VK_RESULT(VK_ERROR_EXTENSION_NOT_PRESENT)
        DAISY_VK_RESULT(VK_ERROR_FEATURE_NOT_PRESENT)
        DAISY_VK_RESULT(VK_ERROR_INCOMPATIBLE_DRIVER)
        DAISY_VK_RESULT(VK_ERROR_TOO_MANY_OBJECTS)
        DAISY_VK_RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED)
        DAISY_VK_RESULT(VK_ERROR_FRAGMENTED_POOL)
        DAISY_VK_RESULT(VK_ERROR_UNKNOWN)
        DAISY_VK_RESULT(VK_ERROR_OUT_OF_POOL_MEMORY)
        DAISY_VK_RESULT(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        DAISY_VK_RESULT(VK_ERROR_FRAGMENTATION)
        DAISY_VK_RESULT(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
        // The window system's results (the viewer's surface and swapchain).
        DAISY_VK_RESULT(VK_ERROR_SURFACE_LOST_KHR)
        DAISY_VK_RESULT(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
        DAISY_VK_RESULT(VK_SUBOPTIMAL_KHR)
        DAISY_VK_RESULT(VK_ERROR_OUT_OF_DATE_KHR)
#undef DAISY_VK_RESULT
        default:
            break;
    }
    static thread_local char text[32];
    std::snprintf(text, sizeof text, "VkResult(%d)", static_cast<int>(result));
    return text;
}

std::string vkErrorMessage(VkResult result, const char* call, const char* file, int line) {
    // The last "/src/" of the path: the source tree's own folder, whatever the checkout is named.
    const char* shortFile = file;
    for (const char* p = std::strstr(file, "/src/"); p; p = std::strstr(p + 1, "/src/"))
        shortFile = p + 1;
    return concat("vulkan: ", call, " failed: ", vkResultName(result), " at ", shortFile, ":",
                  line);
}

}  // namespace daisy
