#pragma once
// The backend registry (DESIGN.md section 8): the one list of form-factor backends, above every
// backend library so that none includes another (cpu and reference live in src/backend/, vulkan
// in the optional daisy_vulkan library, cuda in the optional daisy_cuda library). `auto` picks cuda
// on an NVIDIA device, then vulkan on a discrete or integrated GPU, then cpu.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "backend/backend.h"
#include "core/expected.h"

namespace daisy {

struct BackendEntry {
    const char* name;  // what --backend takes
    // Backends of one family compute the same F up to float rounding (the cpu driver; or the
    // shared pair kernel on our flat BVH): a cached F is shared within a family.
    const char* family;
    bool builtIn;  // compiled into this binary
    const char* notBuiltReason;  // when !builtIn: what to do about it
    // Creates the backend; errors name the missing device or loader. Null when !builtIn.
    Expected<std::unique_ptr<Backend>> (*make)(const BackendOptions& options);
};

// Every backend this project knows, built into this binary or not, in `auto`'s order of
// preference reversed (cpu first).
std::span<const BackendEntry> backendEntries();

// Every name --backend accepts: "auto" first, then each entry's name.
std::vector<std::string> backendNames();

// The names of the backends built into this binary (for `daisy --version`).
std::vector<std::string> builtInBackendNames();

// The backend `name` stands for: "auto" resolved as above (probing for devices), else `name`.
std::string resolveBackendName(const std::string& name);

// The family of a backend name ("cpu", "kernel"); empty for unknown names.
std::string backendFamily(const std::string& name);

// Whether backend `name` could build F here, by a cheap probe and without making it: an error as
// makeBackend's for an unknown or not-built backend, or a missing CUDA or Vulkan device. The
// session checks an explicit --backend with it before reading F from the cache, so that
// `--backend cuda` without a CUDA device fails instead of returning a cached F that another
// backend of its family built.
Expected<void> checkBackendRunsHere(const std::string& name);

// The backend called `name` ("auto" resolves as above). Errors: unknown names, backends not built
// into this binary (with the configure option that builds them), a missing device.
Expected<std::unique_ptr<Backend>> makeBackend(const std::string& name,
                                               const BackendOptions& options = {});

}  // namespace daisy
