#pragma once
// What one thread of the CUDA pair kernel does, and the kernel arguments the host packs for it,
// in plain C++/CUDA without cuda_runtime.h: cuda/pair_kernel.cu runs evaluatePairSlot on the
// device, and tests/cuda/pair_slot_test.cpp runs the same code on the CPU over host arrays to
// check the unpacking and the pass strategy against the reference backend.
#include "shared/config.h"
#include "shared/gpu_types.h"
#include "shared/pair_kernel.h"

namespace daisy {

// Slot params.pairOffset + k of this launch, in pass `mode` (DAISY_PAIR_MODE_*): reads its pair
// and their patches, calls the shared pairEntryInMode, writes both results. params' addresses
// point at arrays this code can read (device pointers on the GPU, host pointers on the CPU).
// Precondition: k < params.pairCount.
DAISY_HD void evaluatePairSlot(const shared::PairKernelParams& params, int mode, shared::uint k) {
    using namespace shared;
    const uint slot = params.pairOffset + k;
    const PairIndex pair = reinterpret_cast<const PairIndex*>(params.pairs)[slot];
    const PatchGeometry* patches = reinterpret_cast<const PatchGeometry*>(params.patches);
    const BvhNodeBuffer nodes{reinterpret_cast<const BvhNode*>(params.nodes)};
    const BvhTriangleBuffer triangles{reinterpret_cast<const BvhTriangle*>(params.triangles)};
    reinterpret_cast<PairFactors*>(params.results)[slot] =
        pairEntryInMode(mode, pair.i, pair.j, patches[pair.i], patches[pair.j], params.method,
                        params.level, params.rays, params.seed, params.clearance, nodes, triangles);
}

}  // namespace daisy
