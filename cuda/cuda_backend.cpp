// The cuda backend: uploads the patches and the flat BVH once a build, then runs the GPU pass
// strategy (backend/gpu_pass_plan.h: visibility first, the hybrid far-field pass, the whole
// kernel for the pairs with a near cell) as the one driver's PairEvaluator. Each pass is
// launches of the pair kernel of its mode (cuda/pair_kernel.cu) sized by planCudaBatches
// (batch_plan.h), double-buffered over two streams and pinned host buffers (double_buffer.h):
// the host packs the next launch's pairs and unpacks the last one's results while the device
// runs. Every CUDA call goes through CUDA_CHECK: failures are Expected errors, never aborts.
#include "cuda/cuda_backend.h"

#include <cuda_runtime.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <tuple>
#include <vector>

#include "backend/gpu_pass_plan.h"
#include "core/log.h"
#include "core/strings.h"
#include "cuda/cuda_check.h"
#include "cuda/double_buffer.h"
#include "cuda/pair_kernel.h"
#include "radiosity/kernel_inputs.h"
#include "raycast/flat_bvh.h"
#include "shared/config.h"

namespace daisy {
namespace {

using shared::PairFactors;
using shared::PairIndex;
using shared::PairKernelParams;

// The oldest architecture this build has code for (CMAKE_CUDA_ARCHITECTURES, docs/gpu.md).
constexpr int kMinComputeCapability = 75;

uint64_t address(const void* pointer) {
    return reinterpret_cast<uint64_t>(pointer);
}

// One side of the double buffer: a stream, pinned host buffers and device buffers of one launch.
struct Slot {
    cudaStream_t stream = nullptr;
    PairIndex* hostPairs = nullptr;
    PairFactors* hostResults = nullptr;
    PairIndex* devicePairs = nullptr;
    PairFactors* deviceResults = nullptr;
};

// What one build holds on the device; released on every path, after its streams are idle. The
// release calls' own errors are ignored: after a failed launch the context may refuse them all.
struct DeviceState {
    void* patches = nullptr;
    void* nodes = nullptr;
    void* triangles = nullptr;
    Slot slots[2];

    DeviceState() = default;
    DeviceState(const DeviceState&) = delete;
    DeviceState& operator=(const DeviceState&) = delete;
    ~DeviceState() {
        for (Slot& slot : slots) {
            if (slot.stream) {
                (void)cudaStreamSynchronize(slot.stream);
                (void)cudaStreamDestroy(slot.stream);
            }
            (void)cudaFreeHost(slot.hostPairs);
            (void)cudaFreeHost(slot.hostResults);
            (void)cudaFree(slot.devicePairs);
            (void)cudaFree(slot.deviceResults);
        }
        for (void* array : {patches, nodes, triangles})
            (void)cudaFree(array);
        (void)cudaGetLastError();  // clear a non-sticky error for the next build
    }
};

// Copies `bytes` of `data` to a new device array (at least 64 bytes, so never empty).
Expected<void> uploadArray(void** array, const void* data, std::size_t bytes) {
    CUDA_CHECK(cudaMalloc(array, std::max<std::size_t>(bytes, 64)));
    if (bytes) CUDA_CHECK(cudaMemcpy(*array, data, bytes, cudaMemcpyHostToDevice));
    return {};
}

Expected<void> createSlot(Slot& slot, std::size_t launchPairs) {
    CUDA_CHECK(cudaStreamCreateWithFlags(&slot.stream, cudaStreamNonBlocking));
    CUDA_CHECK(cudaMallocHost(&slot.hostPairs, launchPairs * sizeof(PairIndex)));
    CUDA_CHECK(cudaMallocHost(&slot.hostResults, launchPairs * sizeof(PairFactors)));
    CUDA_CHECK(cudaMalloc(&slot.devicePairs, launchPairs * sizeof(PairIndex)));
    CUDA_CHECK(cudaMalloc(&slot.deviceResults, launchPairs * sizeof(PairFactors)));
    return {};
}

// The passes' kernels, for their occupancy and stack: the plan takes the worst of them.
constexpr int kPassModes[] = {DAISY_PAIR_MODE_FACTORS, DAISY_PAIR_MODE_VISIBILITY,
                              DAISY_PAIR_MODE_FAR_FIELD};

// The facts planCudaBatches needs, read from the current device and the compiled kernels.
Expected<CudaDeviceFacts> deviceFacts(const cudaDeviceProp& properties) {
    CudaDeviceFacts facts;
    facts.name = properties.name;
    std::size_t freeBytes = 0;
    std::size_t totalBytes = 0;
    CUDA_CHECK(cudaMemGetInfo(&freeBytes, &totalBytes));
    facts.freeBytes = freeBytes;
    facts.smCount = properties.multiProcessorCount;
    facts.maxThreadsPerSm = properties.maxThreadsPerMultiProcessor;
    facts.stackBytesPerThread = 0;
    for (int mode : kPassModes) {
        int blocks = 0;
        CUDA_CHECK(pairKernelBlocksPerSm(mode, &blocks));
        facts.blocksPerSm = mode == kPassModes[0] ? blocks : std::min(facts.blocksPerSm, blocks);
        cudaFuncAttributes attributes{};
        CUDA_CHECK(pairKernelAttributes(mode, &attributes));
        facts.stackBytesPerThread =
            std::max<uint64_t>(facts.stackBytesPerThread, attributes.localSizeBytes);
    }
    int device = 0;
    int watchdog = 0;
    CUDA_CHECK(cudaGetDevice(&device));
    CUDA_CHECK(cudaDeviceGetAttribute(&watchdog, cudaDevAttrKernelExecTimeout, device));
    facts.watchdog = watchdog != 0;
    return facts;
}

// One pass of the pair kernel over a batch's pairs: launches of plan.launchPairs through the two
// slots of the device state.
class CudaPasses final : public PairKernelPasses {
public:
    CudaPasses(int device, const CudaBatchPlan& plan, DeviceState& state,
               const PairKernelParams& params)
        : device_(device), plan_(plan), state_(state), params_(params) {}

    Expected<void> runPass(std::span<const PairIndex> pairs, int mode, int rays,
                           std::span<PairFactors> out) override {
        // The current device is per host thread, and the driver may call from another one.
        CUDA_CHECK(cudaSetDevice(device_));
        const auto submit = [&](int s, std::size_t chunk) -> Expected<void> {
            const ChunkRange range = chunkRange(chunk, plan_.launchPairs, pairs.size());
            Slot& slot = state_.slots[s];
            std::memcpy(slot.hostPairs, pairs.data() + range.first,
                        range.count * sizeof(PairIndex));
            CUDA_CHECK(cudaMemcpyAsync(slot.devicePairs, slot.hostPairs,
                                       range.count * sizeof(PairIndex), cudaMemcpyHostToDevice,
                                       slot.stream));
            PairKernelParams launch = params_;
            launch.pairs = address(slot.devicePairs);
            launch.results = address(slot.deviceResults);
            launch.pairOffset = 0;
            launch.pairCount = uint32_t(range.count);
            launch.rays = rays;
            CUDA_CHECK(launchPairKernel(launch, mode, slot.stream));
            CUDA_CHECK(cudaMemcpyAsync(slot.hostResults, slot.deviceResults,
                                       range.count * sizeof(PairFactors), cudaMemcpyDeviceToHost,
                                       slot.stream));
            return {};
        };
        const auto finish = [&](int s, std::size_t chunk) -> Expected<void> {
            const ChunkRange range = chunkRange(chunk, plan_.launchPairs, pairs.size());
            Slot& slot = state_.slots[s];
            CUDA_CHECK(cudaStreamSynchronize(slot.stream));
            std::memcpy(out.data() + range.first, slot.hostResults,
                        range.count * sizeof(PairFactors));
            return {};
        };
        return runDoubleBuffered(chunkCount(pairs.size(), plan_.launchPairs), submit, finish);
    }

private:
    int device_;
    const CudaBatchPlan& plan_;
    DeviceState& state_;
    PairKernelParams params_;
};

class CudaBackend final : public Backend {
public:
    CudaBackend(int device, const cudaDeviceProp& properties, const CudaBatchLimits& limits)
        : device_(device), properties_(properties), limits_(limits) {}

    std::string name() const override { return "cuda"; }

    Expected<FormFactorResult> buildFormFactors(const PatchMesh& mesh,
                                                const FormFactorSettings& settings) override;

private:
    int device_;
    cudaDeviceProp properties_;
    CudaBatchLimits limits_;
};

Expected<FormFactorResult> CudaBackend::buildFormFactors(const PatchMesh& mesh,
                                                         const FormFactorSettings& settings) {
    Expected<void> pairMethod = checkPairMethod(settings, name());
    if (!pairMethod) return pairMethod.error();
    CUDA_CHECK(cudaSetDevice(device_));
    const std::vector<shared::PatchGeometry> patches = kernelPatches(mesh);
    auto built = buildFlatBvh(mesh);
    if (!built) return built.error();
    const FlatBvh& bvh = *built;
    const std::size_t patchBytes = patches.size() * sizeof(shared::PatchGeometry);
    const std::size_t nodeBytes = bvh.nodes.size() * sizeof(shared::BvhNode);
    const std::size_t triangleBytes = bvh.triangles.size() * sizeof(shared::BvhTriangle);

    auto facts = deviceFacts(properties_);
    if (!facts) return facts.error();
    auto planned = planCudaBatches(*facts, patchBytes + nodeBytes + triangleBytes,
                                   pairWork(settings), limits_);
    if (!planned) return planned.error();
    const CudaBatchPlan plan = *planned;
    logVerbose(concat("cuda: ", facts->blocksPerSm, " blocks of ", plan.blockSize,
                      " threads per SM, ", formatBytes(double(facts->stackBytesPerThread)),
                      " stack a thread; launches of ", formatCount(plan.launchPairs),
                      " pairs, batches of ", formatCount(plan.batchPairs), ", ",
                      formatBytes(double(plan.deviceBytes)), " on the device"));

    DeviceState state;
    for (const auto& [array, data, bytes] :
         {std::tuple{&state.patches, static_cast<const void*>(patches.data()), patchBytes},
          std::tuple{&state.nodes, static_cast<const void*>(bvh.nodes.data()), nodeBytes},
          std::tuple{&state.triangles, static_cast<const void*>(bvh.triangles.data()),
                     triangleBytes}}) {
        Expected<void> uploaded = uploadArray(array, data, bytes);
        if (!uploaded) return uploaded.error();
    }
    for (Slot& slot : state.slots) {
        Expected<void> created = createSlot(slot, plan.launchPairs);
        if (!created) return created.error();
    }

    const PairKernelParams params =
        packPairKernelParams(settings, state.patches, state.nodes, state.triangles);

    CudaPasses passes(device_, plan, state, params);
    GpuPassEvaluator evaluator("cuda", plan.batchPairs, params.method, passes);
    auto result = computeFormFactors(mesh, settings, evaluator);
    logVerbose(evaluator.summary());
    return result;
}

// The devices the runtime sees, or why there are none (one line).
Expected<std::vector<cudaDeviceProp>> listDevices() {
    int count = 0;
    const cudaError_t error = cudaGetDeviceCount(&count);
    if (error != cudaSuccess) {
        // Without libcuda.so at all the runtime also says "insufficient driver".
        const std::string hint = error == cudaErrorInsufficientDriver
            ? concat("; the NVIDIA driver is missing or older than this CUDA ",
                     CUDART_VERSION / 1000, ".", CUDART_VERSION % 1000 / 10, " runtime needs")
            : std::string();
        return Error{concat("no CUDA device (cudaGetDeviceCount: ", cudaGetErrorName(error), ": ",
                            cudaGetErrorString(error), hint, ")")};
    }
    if (count == 0) return Error{"no CUDA device (cudaGetDeviceCount found none)"};
    std::vector<cudaDeviceProp> devices(static_cast<std::size_t>(count));
    for (int d = 0; d < count; ++d)
        CUDA_CHECK(cudaGetDeviceProperties(&devices[std::size_t(d)], d));
    return devices;
}

std::string deviceList(const std::vector<cudaDeviceProp>& devices) {
    std::string list;
    for (std::size_t d = 0; d < devices.size(); ++d) {
        list += concat(d ? ", " : "", d, ": '", devices[d].name, "' sm_", devices[d].major,
                       devices[d].minor);
    }
    return list;
}

// The device --device names: an index, or the first whose name contains the text.
Expected<int> pickDevice(const std::string& selector, const std::vector<cudaDeviceProp>& devices) {
    const std::string found = concat(" (found: ", deviceList(devices), ")");
    if (selector.empty()) return 0;
    if (selector.find_first_not_of("0123456789") == std::string::npos) {
        const unsigned long index = std::strtoul(selector.c_str(), nullptr, 10);
        if (index >= devices.size())
            return Error{
                concat("--device ", selector, ": there is no CUDA device ", selector, found)};
        return int(index);
    }
    for (std::size_t d = 0; d < devices.size(); ++d) {
        if (toLower(devices[d].name).find(toLower(selector)) != std::string::npos) return int(d);
    }
    return Error{
        concat("--device ", selector, ": no CUDA device's name contains '", selector, "'", found)};
}

}  // namespace

Expected<std::unique_ptr<Backend>> makeCudaBackend(const BackendOptions& options,
                                                   const CudaBatchLimits& limits) {
    auto devices = listDevices();
    if (!devices) return devices.error();
    auto picked = pickDevice(options.device, *devices);
    if (!picked) return picked.error();
    const cudaDeviceProp& properties = (*devices)[std::size_t(*picked)];
    if (properties.major * 10 + properties.minor < kMinComputeCapability) {
        return Error{concat("CUDA device '", properties.name, "' is sm_", properties.major,
                            properties.minor, "; this build has code for sm_75 and newer only")};
    }
    CUDA_CHECK(cudaSetDevice(*picked));
    cudaFuncAttributes attributes{};
    // No kernel image for this GPU fails here.
    CUDA_CHECK(pairKernelAttributes(DAISY_PAIR_MODE_FACTORS, &attributes));
    logVerbose(concat("cuda: device ", *picked, " '", properties.name, "' (sm_", properties.major,
                      properties.minor, ", ", properties.multiProcessorCount, " SMs, ",
                      formatBytes(double(properties.totalGlobalMem)), "), pair kernel ",
                      attributes.numRegs, " registers, ",
                      formatBytes(double(attributes.localSizeBytes)), " stack a thread"));
    return std::unique_ptr<Backend>(std::make_unique<CudaBackend>(*picked, properties, limits));
}

Expected<std::unique_ptr<Backend>> makeCudaBackend(const BackendOptions& options) {
    return makeCudaBackend(options, CudaBatchLimits{});
}

bool cudaDevicePresent() {
    static const bool present = [] {
        int count = 0;
        if (cudaGetDeviceCount(&count) != cudaSuccess) return false;
        for (int d = 0; d < count; ++d) {
            int major = 0;
            int minor = 0;
            if (cudaDeviceGetAttribute(&major, cudaDevAttrComputeCapabilityMajor, d) ==
                    cudaSuccess &&
                cudaDeviceGetAttribute(&minor, cudaDevAttrComputeCapabilityMinor, d) ==
                    cudaSuccess &&
                major * 10 + minor >= kMinComputeCapability) {
                return true;
            }
        }
        return false;
    }();
    return present;
}

}  // namespace daisy
