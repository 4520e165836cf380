// The pair kernel for CUDA (DESIGN.md section 8): one thread per unordered pair, running
// evaluatePairSlot (cuda/pair_slot.h: unpack the pair, call the shared pairEntry of
// src/shared/pair_kernel.h, the function the reference backend runs on the CPU and
// shaders/form_factors.comp.glsl on Vulkan). All its arithmetic is in src/shared/. Registers and
// stack per architecture: -Xptxas -v at build.
#include "cuda/pair_kernel.h"
#include "cuda/pair_slot.h"
#include "shared/config.h"

namespace daisy {
namespace {

using namespace daisy::shared;

__global__ void __launch_bounds__(DAISY_PAIR_WORKGROUP_SIZE) pairKernel(PairKernelParams params) {
    const uint k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k < params.pairCount) evaluatePairSlot(params, k);
}

}  // namespace

cudaError_t launchPairKernel(const PairKernelParams& params, cudaStream_t stream) {
    const unsigned blocks =
        (params.pairCount + DAISY_PAIR_WORKGROUP_SIZE - 1) / DAISY_PAIR_WORKGROUP_SIZE;
    pairKernel<<<blocks, DAISY_PAIR_WORKGROUP_SIZE, 0, stream>>>(params);
    return cudaGetLastError();
}

cudaError_t pairKernelAttributes(cudaFuncAttributes* attributes) {
    return cudaFuncGetAttributes(attributes, pairKernel);
}

cudaError_t pairKernelBlocksPerSm(int* blocks) {
    return cudaOccupancyMaxActiveBlocksPerMultiprocessor(blocks, pairKernel,
                                                         DAISY_PAIR_WORKGROUP_SIZE, 0);
}

}  // namespace daisy
