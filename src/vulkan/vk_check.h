#pragma once
// VK_CHECK (STYLE.md rule 7): always-on check of a VkResult for failures that are programmer bugs
// or a broken driver (out of device memory mid-run, device lost). Prints the decoded result, the
// call and file:line, then aborts. Missing devices and unsupported features are not checked this
// way: createContext returns them as Expected errors.
#include <volk.h>

namespace daisy {

// "VK_ERROR_OUT_OF_DEVICE_MEMORY" etc.; "VkResult(<n>)" for values this list does not know.
const char* vkResultName(VkResult result);

namespace detail {
[[noreturn]] void vkCheckFailed(VkResult result, const char* call, const char* file, int line);
}  // namespace detail

}  // namespace daisy

#define VK_CHECK(call)                                                                 \
    do {                                                                               \
        const VkResult daisyVkResult_ = (call);                                        \
        if (daisyVkResult_ != VK_SUCCESS) {                                            \
            ::daisy::detail::vkCheckFailed(daisyVkResult_, #call, __FILE__, __LINE__); \
        }                                                                              \
    } while (0)
