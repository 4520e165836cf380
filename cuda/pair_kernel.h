#pragma once
// Host entry points of cuda/pair_kernel.cu, the `__global__` launchers over the shared pair
// kernel (shared/pair_kernel.h), one per pass (DAISY_PAIR_MODE_*, the passes of
// backend/gpu_pass_plan.h). Only cuda/ includes this (it needs cuda_runtime.h).
#include <cuda_runtime.h>

#include "shared/gpu_types.h"

namespace daisy {

// Queues the pair kernel of pass `mode` on `stream` over params.pairCount pairs (blocks of
// DAISY_PAIR_WORKGROUP_SIZE threads; params' addresses are device pointers) and returns
// cudaGetLastError(): a bad configuration fails here, a fault in the kernel at the stream's sync.
cudaError_t launchPairKernel(const shared::PairKernelParams& params, int mode, cudaStream_t stream);

// The compiled kernel of pass `mode`: its registers and local memory (cudaFuncGetAttributes) and
// its resident blocks per SM at DAISY_PAIR_WORKGROUP_SIZE threads (occupancy), on the current
// device.
cudaError_t pairKernelAttributes(int mode, cudaFuncAttributes* attributes);
cudaError_t pairKernelBlocksPerSm(int mode, int* blocks);

}  // namespace daisy
