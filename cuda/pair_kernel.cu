// The pair kernel for CUDA (DESIGN.md section 8): one thread per unordered pair, running
// evaluatePairSlot (cuda/pair_slot.h: unpack the pair, call the shared pairEntryInMode of
// src/shared/pair_kernel.h, what shaders/form_factors.comp.glsl runs on Vulkan and the reference
// backend's pairEntry on the CPU). One kernel per pass (DAISY_PAIR_MODE_*), the mode a template
// constant, so each holds only its pass's code, as the Vulkan pipelines are specialised. All its
// arithmetic is in src/shared/. Registers and stack per architecture: -Xptxas -v at build.
#include "cuda/pair_kernel.h"
#include "cuda/pair_slot.h"
#include "shared/config.h"

namespace daisy {
namespace {

using namespace daisy::shared;

template <int kMode>
__global__ void __launch_bounds__(DAISY_PAIR_WORKGROUP_SIZE) pairKernel(PairKernelParams params) {
    const uint k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k < params.pairCount) evaluatePairSlot(params, kMode, k);
}

// The kernel of `mode`; FACTORS for an unknown one.
const void* kernelOf(int mode) {
    if (mode == DAISY_PAIR_MODE_VISIBILITY)
        return reinterpret_cast<const void*>(&pairKernel<DAISY_PAIR_MODE_VISIBILITY>);
    if (mode == DAISY_PAIR_MODE_FAR_FIELD)
        return reinterpret_cast<const void*>(&pairKernel<DAISY_PAIR_MODE_FAR_FIELD>);
    return reinterpret_cast<const void*>(&pairKernel<DAISY_PAIR_MODE_FACTORS>);
}

}  // namespace

cudaError_t launchPairKernel(const PairKernelParams& params, int mode, cudaStream_t stream) {
    const unsigned blocks =
        (params.pairCount + DAISY_PAIR_WORKGROUP_SIZE - 1) / DAISY_PAIR_WORKGROUP_SIZE;
    if (mode == DAISY_PAIR_MODE_VISIBILITY) {
        pairKernel<DAISY_PAIR_MODE_VISIBILITY>
            <<<blocks, DAISY_PAIR_WORKGROUP_SIZE, 0, stream>>>(params);
    } else if (mode == DAISY_PAIR_MODE_FAR_FIELD) {
        pairKernel<DAISY_PAIR_MODE_FAR_FIELD>
            <<<blocks, DAISY_PAIR_WORKGROUP_SIZE, 0, stream>>>(params);
    } else {
        pairKernel<DAISY_PAIR_MODE_FACTORS>
            <<<blocks, DAISY_PAIR_WORKGROUP_SIZE, 0, stream>>>(params);
    }
    return cudaGetLastError();
}

cudaError_t pairKernelAttributes(int mode, cudaFuncAttributes* attributes) {
    return cudaFuncGetAttributes(attributes, kernelOf(mode));
}

cudaError_t pairKernelBlocksPerSm(int mode, int* blocks) {
    return cudaOccupancyMaxActiveBlocksPerMultiprocessor(blocks, kernelOf(mode),
                                                         DAISY_PAIR_WORKGROUP_SIZE, 0);
}

}  // namespace daisy
