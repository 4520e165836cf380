#include "cuda/batch_plan.h"

#include <algorithm>

#include "backend/gpu_pass_plan.h"
#include "core/strings.h"
#include "radiosity/kernel_inputs.h"
#include "shared/config.h"

namespace daisy {

Expected<CudaBatchPlan> planCudaBatches(const CudaDeviceFacts& device, uint64_t sceneBytes,
                                        uint64_t pairWork, const CudaBatchLimits& limits) {
    CudaBatchPlan plan;
    plan.blockSize = DAISY_PAIR_WORKGROUP_SIZE;
    const uint64_t block = plan.blockSize;
    const uint64_t sms = uint64_t(std::max(device.smCount, 1));
    plan.stackBytes =
        device.stackBytesPerThread * sms * uint64_t(std::max(device.maxThreadsPerSm, 0));
    const uint64_t usable = uint64_t(double(device.freeBytes) * kCudaMemoryFraction);
    const uint64_t fixedBytes = sceneBytes + plan.stackBytes;
    const uint64_t smallest = 2 * block * kCudaSlotBytesPerPair;  // two slots of one block
    if (fixedBytes + smallest > usable) {
        return Error{concat("the cuda backend needs ", formatBytes(double(sceneBytes)),
                            " on the device for the patches and BVH and ",
                            formatBytes(double(plan.stackBytes)),
                            " for the pair kernel's stack, but '", device.name, "' has ",
                            formatBytes(double(device.freeBytes)),
                            " free; use a larger --subdivide or --backend cpu")};
    }
    // Waves of resident threads, then the watchdog's work cap and the memory left.
    const uint64_t resident = sms * uint64_t(std::max(device.blocksPerSm, 1)) * block;
    uint64_t launch = resident * kCudaWavesPerLaunch;
    if (device.watchdog)
        launch = std::min(launch, launchPairsForWork(kCudaWatchdogLaunchWork, pairWork, block));
    launch = std::min(launch, (usable - fixedBytes) / (2 * kCudaSlotBytesPerPair));
    if (limits.launchPairs) launch = limits.launchPairs;
    // pairCount is a uint in PairKernelParams.
    launch = std::min<uint64_t>(launch, uint64_t(1) << 31);
    if (!limits.launchPairs) launch = std::max(block, launch / block * block);
    plan.launchPairs = std::size_t(launch);
    plan.batchPairs =
        limits.batchPairs ? limits.batchPairs : std::size_t(launch * kCudaLaunchesPerBatch);
    plan.deviceBytes = fixedBytes + 2 * launch * kCudaSlotBytesPerPair;
    return plan;
}

shared::PairKernelParams packPairKernelParams(const FormFactorSettings& settings,
                                              const void* patches, const void* nodes,
                                              const void* triangles) {
    shared::PairKernelParams params{};
    params.patches = reinterpret_cast<uint64_t>(patches);
    params.nodes = reinterpret_cast<uint64_t>(nodes);
    params.triangles = reinterpret_cast<uint64_t>(triangles);
    const KernelSettings kernel = kernelSettings(settings);  // as every backend passes them
    params.method = kernel.method;
    params.level = kernel.level;
    params.seed = kernel.seed;
    params.clearance = kernel.clearanceRelative;
    return params;
}

}  // namespace daisy
