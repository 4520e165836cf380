#include "pipeline/backend_registry.h"

#include "core/strings.h"

#if DAISY_HAVE_VULKAN
#include "vulkan/context.h"
#include "vulkan/vulkan_backend.h"
#endif
#if DAISY_HAVE_CUDA
#include "cuda/cuda_backend.h"
#endif

namespace daisy {
namespace {

Expected<std::unique_ptr<Backend>> makeCpu(const BackendOptions&) {
    return makeCpuBackend();
}

Expected<std::unique_ptr<Backend>> makeReference(const BackendOptions&) {
    return makeReferenceBackend();
}

#if DAISY_HAVE_VULKAN
Expected<std::unique_ptr<Backend>> makeVulkan(const BackendOptions& options) {
    return makeVulkanBackend(options);
}
#endif

#if DAISY_HAVE_CUDA
Expected<std::unique_ptr<Backend>> makeCuda(const BackendOptions& options) {
    return makeCudaBackend(options);
}
#endif

const BackendEntry kEntries[] = {
    {"cpu", "cpu", true, "", makeCpu},
    {"reference", "kernel", true, "", makeReference},
#if DAISY_HAVE_VULKAN
    {"vulkan", "kernel", true, "", makeVulkan},
#else
    {"vulkan", "kernel", false, "configure with -DDAISY_ENABLE_VULKAN=ON", nullptr},
#endif
#if DAISY_HAVE_CUDA
    {"cuda", "kernel", true, "", makeCuda},
#else
    {"cuda", "kernel", false, "configure where CMake finds nvcc, or with -DDAISY_ENABLE_CUDA=ON",
     nullptr},
#endif
};

const BackendEntry* findEntry(const std::string& name) {
    for (const BackendEntry& entry : kEntries)
        if (name == entry.name) return &entry;
    return nullptr;
}

}  // namespace

std::span<const BackendEntry> backendEntries() {
    return kEntries;
}

std::vector<std::string> backendNames() {
    std::vector<std::string> names{"auto"};
    for (const BackendEntry& entry : kEntries)
        names.push_back(entry.name);
    return names;
}

std::vector<std::string> builtInBackendNames() {
    std::vector<std::string> names;
    for (const BackendEntry& entry : kEntries)
        if (entry.builtIn) names.push_back(entry.name);
    return names;
}

std::string backendFamily(const std::string& name) {
    const BackendEntry* entry = findEntry(name);
    return entry ? entry->family : "";
}

std::string resolveBackendName(const std::string& name) {
    if (name != "auto") return name;
#if DAISY_HAVE_CUDA
    if (cudaDevicePresent()) return "cuda";
#endif
#if DAISY_HAVE_VULKAN
    if (vulkanHardwareGpuPresent()) return "vulkan";
#endif
    return "cpu";
}

namespace {

// The entry of `name`, or the error makeBackend gives for an unknown or not-built backend.
Expected<const BackendEntry*> builtInEntry(const std::string& name) {
    const BackendEntry* entry = findEntry(name);
    if (!entry) {
        std::string known;
        for (const std::string& n : backendNames())
            known += (known.empty() ? "" : ", ") + n;
        return Error{concat("unknown backend '", name, "' (expected one of ", known, ")")};
    }
    if (!entry->builtIn) {
        std::string built;
        for (const std::string& n : builtInBackendNames())
            built += (built.empty() ? "" : ", ") + n;
        return Error{concat("backend '", name, "' is not built into this binary (",
                            entry->notBuiltReason, "; built in: ", built, ")")};
    }
    return entry;
}

}  // namespace

Expected<void> checkBackendRunsHere(const std::string& requested) {
    const std::string name = resolveBackendName(requested);
    auto entry = builtInEntry(name);
    if (!entry) return entry.error();
#if DAISY_HAVE_CUDA
    if (name == "cuda" && !cudaDevicePresent()) {
        return Error{"no CUDA device here (use --backend auto, cpu or vulkan)"};
    }
#endif
#if DAISY_HAVE_VULKAN
    if (name == "vulkan") {
        auto devices = listVulkanDevices();
        if (!devices) return devices.error();
        bool usable = false;
        for (const VulkanDeviceInfo& device : *devices)
            usable = usable || device.unsupported.empty();
        if (!usable) return Error{"no Vulkan device here can run the compute backend"};
    }
#endif
    return {};
}

Expected<std::unique_ptr<Backend>> makeBackend(const std::string& requested,
                                               const BackendOptions& options) {
    const std::string name = resolveBackendName(requested);
    auto entry = builtInEntry(name);
    if (!entry) return entry.error();
    return (*entry)->make(options);
}

}  // namespace daisy
