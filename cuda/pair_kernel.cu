// The pair kernel for CUDA (DESIGN.md section 8): one thread per unordered pair; the body only
// unpacks its pair and calls the shared pairEntry (src/shared/pair_kernel.h), the function the
// reference backend runs on the CPU and shaders/form_factors.comp.glsl on Vulkan. All its
// arithmetic is in src/shared/. Registers and stack per architecture: -Xptxas -v at build.
#include "cuda/pair_kernel.h"
#include "shared/config.h"
#include "shared/pair_kernel.h"

namespace daisy {
namespace {

using namespace daisy::shared;

__global__ void __launch_bounds__(DAISY_PAIR_WORKGROUP_SIZE) pairKernel(PairKernelParams params) {
    const uint k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= params.pairCount) return;
    const uint slot = params.pairOffset + k;
    const PairIndex pair = reinterpret_cast<const PairIndex*>(params.pairs)[slot];
    const PatchGeometry* patches = reinterpret_cast<const PatchGeometry*>(params.patches);
    const BvhNodeBuffer nodes{reinterpret_cast<const BvhNode*>(params.nodes)};
    const BvhTriangleBuffer triangles{reinterpret_cast<const BvhTriangle*>(params.triangles)};
    reinterpret_cast<PairFactors*>(params.results)[slot] =
        pairEntry(pair.i, pair.j, patches[pair.i], patches[pair.j], params.method, params.level,
                  params.rays, params.seed, params.clearance, nodes, triangles);
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
