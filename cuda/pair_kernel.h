#pragma once
// Host entry points of cuda/pair_kernel.cu, the `__global__` launcher over the shared pair
// kernel (shared/pair_kernel.h). Only cuda/ includes this (it needs cuda_runtime.h).
#include <cuda_runtime.h>

#include "shared/gpu_types.h"

namespace daisy {

// Queues the pair kernel on `stream` over params.pairCount pairs (blocks of
// DAISY_PAIR_WORKGROUP_SIZE threads; params' addresses are device pointers) and returns
// cudaGetLastError(): a bad configuration fails here, a fault in the kernel at the stream's sync.
cudaError_t launchPairKernel(const shared::PairKernelParams& params, cudaStream_t stream);

// The compiled kernel's registers and local memory (cudaFuncGetAttributes) and its resident
// blocks per SM at DAISY_PAIR_WORKGROUP_SIZE threads (occupancy), on the current device.
cudaError_t pairKernelAttributes(cudaFuncAttributes* attributes);
cudaError_t pairKernelBlocksPerSm(int* blocks);

}  // namespace daisy
