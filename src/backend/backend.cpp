#include "backend/backend.h"

#include "core/strings.h"

namespace daisy {

std::vector<std::string> backendNames() {
    return {"auto", "cpu", "reference", "vulkan", "cuda"};
}

Expected<std::unique_ptr<Backend>> makeBackend(const std::string& name,
                                               const BackendOptions& options) {
    (void)options;  // TODO(issue 8): vulkan device selection
    if (name == "auto" || name == "cpu") return makeCpuBackend();
    for (const std::string& known : backendNames()) {
        if (name == known) {
            return Error{concat("backend '", name,
                                "' is not built yet (available: cpu, or auto, which picks cpu)")};
        }
    }
    return Error{
        concat("unknown backend '", name, "' (expected auto, cpu, reference, vulkan or cuda)")};
}

}  // namespace daisy
