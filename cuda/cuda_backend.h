#pragma once
// The cuda backend (DESIGN.md section 8, docs/gpu.md): the shared pair kernel
// (shared/pair_kernel.h) as a thin `__global__` launcher (cuda/pair_kernel.cu) over our flat BVH,
// on an NVIDIA GPU. No CUDA types in this header: the registry (pipeline/) includes it.
#include <memory>

#include "backend/backend.h"
#include "core/expected.h"
#include "cuda/batch_plan.h"

namespace daisy {

// The backend on the device options.device selects (index or part of its name, case-insensitive;
// empty = device 0). Error, one line, when there is no driver, no device or no match.
Expected<std::unique_ptr<Backend>> makeCudaBackend(const BackendOptions& options);
Expected<std::unique_ptr<Backend>> makeCudaBackend(const BackendOptions& options,
                                                   const CudaBatchLimits& limits);

// True when the CUDA runtime finds a device this build has code for, compute capability 7.5 or
// newer (what `--backend auto` asks first).
bool cudaDevicePresent();

}  // namespace daisy
