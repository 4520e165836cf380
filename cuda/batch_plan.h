#pragma once
// How the cuda backend cuts the driver's pairs into kernel launches and packs their arguments
// (docs/gpu.md): pure host code over a few device facts, so it is unit-tested without a device
// (tests/cuda/batch_plan_test.cpp, pair_slot_test.cpp). No CUDA types here. The passes each batch
// runs are the shared GPU pass strategy (backend/gpu_pass_plan.h).
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/expected.h"
#include "radiosity/form_factors.h"
#include "shared/gpu_types.h"

namespace daisy {

// What the plan needs to know about the device and the compiled pair kernel.
struct CudaDeviceFacts {
    std::string name;  // for messages
    uint64_t freeBytes = 0;  // device memory free now (cudaMemGetInfo)
    int smCount = 0;  // streaming multiprocessors
    int maxThreadsPerSm = 0;  // resident threads an SM can hold (2048 on sm_80/sm_90)
    int blocksPerSm = 0;  // resident pair-kernel blocks per SM at its register use (occupancy)
    uint64_t stackBytesPerThread = 0;  // the pair kernel's local memory a thread (localSizeBytes)
    bool watchdog = false;  // a display watchdog limits how long one launch may run
};

// Sizes the tests may force (0 = from the device), as VulkanBackendLimits does for vulkan.
struct CudaBatchLimits {
    std::size_t launchPairs = 0;
    std::size_t batchPairs = 0;
};

struct CudaBatchPlan {
    std::size_t blockSize = 0;  // threads a block (DAISY_PAIR_WORKGROUP_SIZE)
    std::size_t launchPairs = 0;  // pairs a kernel launch (one slot of the double buffer)
    std::size_t batchPairs = 0;  // pairs the driver hands over at once: several launches
    uint64_t stackBytes = 0;  // local memory the driver reserves for the kernel's stack
    uint64_t deviceBytes = 0;  // everything on the device: scene arrays, stack, two slots
};

// Device bytes of one launch slot per pair: a PairIndex in and a PairFactors out.
inline constexpr uint64_t kCudaSlotBytesPerPair = 16;
// A launch is this many waves of resident threads: enough that the last, partial wave and the
// launch overhead are small, few enough that a batch holds several launches to overlap.
inline constexpr uint64_t kCudaWavesPerLaunch = 4;
// Launches per batch: the host packs one while the device runs another (two streams).
inline constexpr uint64_t kCudaLaunchesPerBatch = 4;
// Work units (shadow segments plus quadrature points: pairWork, backend/gpu_pass_plan.h) of one
// launch on a GPU with a display watchdog (~2 s on Windows): ~10 ms at the ~2e9 units/s of a
// current GPU.
inline constexpr uint64_t kCudaWatchdogLaunchWork = uint64_t(1) << 24;
// Fraction of the free memory the plan may use; the rest is left to the driver and the display.
inline constexpr double kCudaMemoryFraction = 0.9;

// The plan for a scene whose patches and BVH take sceneBytes on the device, each pair costing
// pairWork units: launches of kCudaWavesPerLaunch waves of smCount * blocksPerSm blocks (capped
// by the watchdog's work and by memory), whole blocks; batches of kCudaLaunchesPerBatch
// launches. The stack reservation is stackBytesPerThread for every thread the device can hold
// (smCount * maxThreadsPerSm), what the CUDA driver sets aside for a kernel's local memory.
// Error (naming the device and the sizes) when the scene and the stack leave no room for a launch.
Expected<CudaBatchPlan> planCudaBatches(const CudaDeviceFacts& device, uint64_t sceneBytes,
                                        uint64_t pairWork, const CudaBatchLimits& limits = {});

// The pair kernel's arguments for a build: the device addresses of the scene arrays and the
// settings as every pair-kernel backend passes them to pairEntry (kernelSettings,
// radiosity/kernel_inputs.h). The per-launch fields (pairs,
// results, pairOffset, pairCount, rays) are zero, for the caller to fill.
shared::PairKernelParams packPairKernelParams(const FormFactorSettings& settings,
                                              const void* patches, const void* nodes,
                                              const void* triangles);

}  // namespace daisy
