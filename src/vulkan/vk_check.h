#pragma once
// VK_CHECK (STYLE.md rule 7): every Vulkan call of daisy_vulkan and the viewer whose VkResult can
// fail goes through it. Any result other than VK_SUCCESS returns an Error from the enclosing
// function (which returns Expected<...>) naming the call, the decoded result and file:line; the
// command then exits 2 with that one line. Nothing aborts: out of device memory, a lost device or
// a failed submit is a message. Results that are not failures where they occur
// (VK_SUBOPTIMAL_KHR, VK_ERROR_OUT_OF_DATE_KHR on acquire and present) are handled before
// VK_CHECK. Cleanup that cannot return (destructors, destroy* functions) ignores results.
#include <volk.h>

#include <string>

#include "core/expected.h"

namespace daisy {

// "VK_ERROR_OUT_OF_DEVICE_MEMORY" etc.; "VkResult(<n>)" for values this list does not know.
const char* vkResultName(VkResult result);

// "vulkan: <call> failed: <vkResultName> at <file>:<line>", `file` shortened to the part from
// its last "/src/" on (e.g. "src/vulkan/buffers.cpp"), whatever the checkout is named.
std::string vkErrorMessage(VkResult result, const char* call, const char* file, int line);

}  // namespace daisy

#define VK_CHECK(call)                                                               \
    do {                                                                             \
        const VkResult daisyVkResult_ = (call);                                      \
        if (daisyVkResult_ != VK_SUCCESS) {                                          \
            return ::daisy::Error{                                                   \
                ::daisy::vkErrorMessage(daisyVkResult_, #call, __FILE__, __LINE__)}; \
        }                                                                            \
    } while (0)
