// The vulkan backend: uploads the patches and the flat BVH once, then runs the GPU pass strategy
// (backend/gpu_pass_plan.h: V first and the quadrature only for the pairs some segment gets
// through; the hybrid quadrature without the adaptive refinement, then with it for the pairs that
// have a near cell) as the one driver's PairEvaluator. Each pass uploads its pairs, runs
// shaders/form_factors.comp.glsl over them in dispatches short enough for a display watchdog, and
// downloads the results, each pass a pipeline specialised to the method, level and mode
// (docs/backends.md). Every buffer stays within the device's maxStorageBufferRange (128 MiB on
// lavapipe): batches are sized to it, and a scene whose patch or BVH arrays exceed it is refused.
#include "vulkan/vulkan_backend.h"

#include <algorithm>
#include <array>
#include <map>
#include <tuple>
#include <vector>

#include "backend/gpu_pass_plan.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "radiosity/kernel_inputs.h"
#include "raycast/flat_bvh.h"
#include "shared/config.h"
#include "shared/gpu_types.h"
#include "vulkan/buffers.h"
#include "vulkan/context.h"
#include "vulkan/pipelines.h"
#include "vulkan/vk_check.h"

namespace daisy {
namespace {

using shared::PairFactors;
using shared::PairIndex;
using shared::PairKernelParams;

// Pairs per batch: 16 MiB of pairs and results on the device and in the driver's host batch,
// large enough that the per-batch upload, submit and download cost is noise next to the kernel.
constexpr std::size_t kBatchPairs = std::size_t(1) << 20;

// Work units per dispatch, a unit being one shadow segment or one quadrature point of a pair
// (pairWork). Desktop drivers kill a submission that runs for ~2 s (Windows TDR; Linux amdgpu and
// i915 job timeouts are longer); software BVH traversal on a mid-range GPU does ~1e8-1e9 units/s,
// so 2^22 units are ~5-40 ms, leaving two orders of magnitude of margin for slow GPUs and hard
// pairs (hybrid refinement near shared edges). Lavapipe, which has no watchdog, does ~8e5/s on
// the 2-core benchmark machine (docs/performance.md), so a dispatch takes it seconds.
constexpr uint64_t kDispatchWork = uint64_t(1) << 22;

class VulkanBackend : public Backend {
public:
    VulkanBackend(VulkanContext context, const VulkanBackendLimits& limits)
        : context_(context), limits_(limits) {}
    ~VulkanBackend() override {
        for (auto& [key, pipeline] : pipelines_)
            destroyComputePipeline(context_, pipeline);
        destroyContext(context_);
    }
    VulkanBackend(const VulkanBackend&) = delete;
    VulkanBackend& operator=(const VulkanBackend&) = delete;

    std::string name() const override { return "vulkan"; }

    Expected<FormFactorResult> buildFormFactors(const PatchMesh& mesh,
                                                const FormFactorSettings& settings) override;

private:
    // Largest buffer in bytes: the device's maxStorageBufferRange unless a test lowers it.
    uint64_t bufferLimit() const {
        const uint64_t device = context_.properties.limits.maxStorageBufferRange;
        return limits_.storageBufferBytes ? std::min(limits_.storageBufferBytes, device) : device;
    }

    Expected<VulkanBuffer> uploadArray(const void* data, std::size_t bytes, const char* what,
                                       std::size_t count);

    // The pair kernel specialised to (method constant, level, DAISY_PAIR_MODE_*)
    // (shaders/form_factors.comp.glsl), compiled on first use and kept for the next build.
    Expected<const ComputePipeline*> pipeline(int method, int level, int mode) {
        const std::array<int32_t, 3> key{method, level, mode};
        auto found = pipelines_.find(key);
        if (found == pipelines_.end()) {
            auto created = createComputePipeline(context_, embeddedSpirv("form_factors.comp"),
                                                 sizeof(PairKernelParams), key);
            if (!created) return created.error();
            found = pipelines_.emplace(key, *created).first;
        }
        return &found->second;
    }

    VulkanContext context_;
    VulkanBackendLimits limits_;
    std::map<std::array<int32_t, 3>, ComputePipeline> pipelines_;
};

Expected<VulkanBuffer> VulkanBackend::uploadArray(const void* data, std::size_t bytes,
                                                  const char* what, std::size_t count) {
    if (bytes > bufferLimit()) {
        return Error{concat(
            "the vulkan backend keeps the ", what, " in one storage buffer: ", formatCount(count),
            " need ", formatBytes(double(bytes)), ", more than this device's limit of ",
            formatBytes(double(bufferLimit())), " (maxStorageBufferRange on '",
            context_.properties.deviceName, "'); use a larger --subdivide or --backend cpu")};
    }
    // Vulkan buffers cannot be empty; a 1-patch scene still gets 64 bytes.
    auto buffer = createBuffer(context_, std::max<std::size_t>(bytes, 64));
    if (!buffer) return buffer.error();
    if (auto uploaded = upload(context_, *buffer, data, bytes); !uploaded) {
        destroyBuffer(context_, *buffer);
        return uploaded.error();
    }
    return buffer;
}

Expected<FormFactorResult> VulkanBackend::buildFormFactors(const PatchMesh& mesh,
                                                           const FormFactorSettings& settings) {
    Expected<void> pairMethod = checkPairMethod(settings, name());
    if (!pairMethod) return pairMethod.error();
    const std::vector<shared::PatchGeometry> patches = kernelPatches(mesh);
    auto built = buildFlatBvh(mesh);
    if (!built) return built.error();
    const FlatBvh& bvh = *built;
    std::vector<VulkanBuffer> owned;
    const auto release = [&] {
        for (VulkanBuffer& buffer : owned)
            destroyBuffer(context_, buffer);
    };
    for (const auto& [data, bytes, what, count] :
         {std::tuple{static_cast<const void*>(patches.data()),
                     patches.size() * sizeof(shared::PatchGeometry), "patches", patches.size()},
          std::tuple{static_cast<const void*>(bvh.nodes.data()),
                     bvh.nodes.size() * sizeof(shared::BvhNode), "BVH nodes", bvh.nodes.size()},
          std::tuple{static_cast<const void*>(bvh.triangles.data()),
                     bvh.triangles.size() * sizeof(shared::BvhTriangle), "BVH triangles",
                     bvh.triangles.size()}}) {
        auto buffer = uploadArray(data, bytes, what, count);
        if (!buffer) {
            release();
            return buffer.error();
        }
        owned.push_back(*buffer);
    }

    // Batches: pairs and results are 8 bytes each, so both buffers fit the limit.
    const uint64_t pairLimit = bufferLimit() / std::max(sizeof(PairIndex), sizeof(PairFactors));
    const std::size_t batchPairs = std::size_t(std::max<uint64_t>(
        1, std::min<uint64_t>(limits_.batchPairs ? limits_.batchPairs : kBatchPairs, pairLimit)));
    // Dispatches: kDispatchWork units, whole workgroups, within maxComputeWorkGroupCount[0].
    const uint64_t groupLimit = uint64_t(context_.properties.limits.maxComputeWorkGroupCount[0]) *
        DAISY_PAIR_WORKGROUP_SIZE;
    uint64_t dispatchPairs = limits_.dispatchPairs
        ? limits_.dispatchPairs
        : launchPairsForWork(kDispatchWork, pairWork(settings), DAISY_PAIR_WORKGROUP_SIZE);
    dispatchPairs = std::min(dispatchPairs, groupLimit);

    for (const std::size_t bytes :
         {batchPairs * sizeof(PairIndex), batchPairs * sizeof(PairFactors)}) {
        auto buffer = createBuffer(context_, bytes);
        if (!buffer) {
            release();
            return buffer.error();
        }
        owned.push_back(*buffer);
    }
    const VulkanBuffer pairBuffer = owned[3];
    const VulkanBuffer resultBuffer = owned[4];

    PairKernelParams params{};
    params.patches = owned[0].address;
    params.nodes = owned[1].address;
    params.triangles = owned[2].address;
    params.pairs = pairBuffer.address;
    params.results = resultBuffer.address;
    const KernelSettings kernel = kernelSettings(settings);  // as every backend passes them
    params.method = kernel.method;
    params.level = kernel.level;
    params.seed = kernel.seed;
    params.clearance = kernel.clearanceRelative;

    // One pass: the kernel specialised to `mode` over pairs (at most batchPairs) into out.
    struct Passes final : PairKernelPasses {
        VulkanBackend& backend;
        PairKernelParams& params;
        const VulkanBuffer& pairBuffer;
        const VulkanBuffer& resultBuffer;
        uint64_t dispatchPairs;

        Passes(VulkanBackend& b, PairKernelParams& p, const VulkanBuffer& pairs,
               const VulkanBuffer& results, uint64_t dispatch)
            : backend(b),
              params(p),
              pairBuffer(pairs),
              resultBuffer(results),
              dispatchPairs(dispatch) {}

        Expected<void> runPass(std::span<const PairIndex> pairs, int mode, int rays,
                               std::span<PairFactors> out) override {
            const VulkanContext& context = backend.context_;
            auto made = backend.pipeline(params.method, params.level, mode);
            if (!made) return made.error();
            const ComputePipeline& kernel = **made;
            params.rays = rays;
            auto uploaded = upload(context, pairBuffer, pairs.data(), pairs.size_bytes());
            if (!uploaded) return uploaded;
            for (std::size_t first = 0; first < pairs.size(); first += dispatchPairs) {
                params.pairOffset = uint32_t(first);
                params.pairCount =
                    uint32_t(std::min<uint64_t>(dispatchPairs, pairs.size() - first));
                const uint32_t groups =
                    (params.pairCount + DAISY_PAIR_WORKGROUP_SIZE - 1) / DAISY_PAIR_WORKGROUP_SIZE;
                // One submission per dispatch: a watchdog sees one short job at a time.
                auto ran = submitAndWait(context, [&](VkCommandBuffer commands) {
                    vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.pipeline);
                    vkCmdPushConstants(commands, kernel.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                                       sizeof params, &params);
                    vkCmdDispatch(commands, groups, 1, 1);
                    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
                    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
                    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
                    vkCmdPipelineBarrier(
                        commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &barrier,
                        0, nullptr, 0, nullptr);
                });
                if (!ran) return ran;
            }
            return download(context, resultBuffer, out.data(), out.size_bytes());
        }
    };
    Passes passes(*this, params, pairBuffer, resultBuffer, dispatchPairs);
    GpuPassEvaluator evaluator("vulkan", batchPairs, params.method, passes);
    auto result = computeFormFactors(mesh, settings, evaluator);
    logVerbose(evaluator.summary());
    release();
    return result;
}

}  // namespace

Expected<std::unique_ptr<Backend>> makeVulkanBackend(const BackendOptions& options,
                                                     const VulkanBackendLimits& limits) {
    auto context = createContext(options.device);
    if (!context) return context.error();
    logVerbose(concat("vulkan: device '", context->properties.deviceName, "' (",
                      deviceTypeName(context->properties.deviceType), ", Vulkan ",
                      VK_API_VERSION_MAJOR(context->properties.apiVersion), ".",
                      VK_API_VERSION_MINOR(context->properties.apiVersion),
                      "), largest storage buffer ",
                      formatBytes(double(context->properties.limits.maxStorageBufferRange))));
    return std::unique_ptr<Backend>(std::make_unique<VulkanBackend>(*context, limits));
}

Expected<std::unique_ptr<Backend>> makeVulkanBackend(const BackendOptions& options) {
    return makeVulkanBackend(options, VulkanBackendLimits{});
}

bool vulkanHardwareGpuPresent() {
    static const bool present = [] {
        auto devices = listVulkanDevices();
        if (!devices) return false;
        for (const VulkanDeviceInfo& device : *devices) {
            const bool gpu = device.type == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU ||
                device.type == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU;
            if (gpu && device.unsupported.empty()) return true;
        }
        return false;
    }();
    return present;
}

}  // namespace daisy
