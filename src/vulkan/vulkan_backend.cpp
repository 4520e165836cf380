// The vulkan backend: uploads the patches and the flat BVH once, then runs the GPU pass strategy
// (backend/gpu_pass_plan.h: V first and the quadrature only for the pairs some segment gets
// through; the hybrid quadrature without the adaptive refinement, then with it for the pairs that
// have a near cell) as the one driver's PairEvaluator. Each pass uploads its pairs, runs
// shaders/form_factors.comp.glsl over them in dispatches short enough for a display watchdog, and
// downloads the results, each pass a pipeline specialised to the method, level and mode
// (docs/backends.md). The visibility pass traces its segments with ray queries through
// acceleration structures over the patches (vulkan/acceleration.h) where the device has them,
// else by walking the flat BVH in the shader. Every buffer stays within the device's
// maxStorageBufferRange (128 MiB on lavapipe): batches are sized to it, and a scene whose patch or
// BVH arrays exceed it is refused.
#include "vulkan/vulkan_backend.h"

#include <algorithm>
#include <array>
#include <map>
#include <string>
#include <tuple>
#include <utility>
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
#include "vulkan/acceleration.h"
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

// "12.3 ms": the short stages of a build, which formatDuration would show as 0.0 s.
std::string milliseconds(double seconds) {
    return concat(formatNumber(seconds * 1e3, 3), " ms");
}

// How the backend traces: ray queries or the BVH walk, and why (for --verbose and `daisy info`).
struct RayTracing {
    bool query = false;
    std::string description;
};

class VulkanBackend : public Backend {
public:
    VulkanBackend(VulkanContext context, const VulkanBackendLimits& limits, RayTracing rays)
        : context_(context), limits_(limits), rays_(std::move(rays)) {}
    ~VulkanBackend() override {
        for (auto& [key, pipeline] : pipelines_)
            destroyComputePipeline(context_, pipeline);
        destroyContext(context_);
    }
    VulkanBackend(const VulkanBackend&) = delete;
    VulkanBackend& operator=(const VulkanBackend&) = delete;

    std::string name() const override { return "vulkan"; }
    std::string describe() const override {
        return concat("device '", context_.properties.deviceName, "' (",
                      deviceTypeName(context_.properties.deviceType),
                      "); shadow rays: ", rays_.description);
    }

    Expected<FormFactorResult> buildFormFactors(const PatchMesh& mesh,
                                                const FormFactorSettings& settings) override;

private:
    // Largest buffer in bytes: the device's maxStorageBufferRange unless a test lowers it.
    uint64_t bufferLimit() const {
        const uint64_t device = context_.properties.limits.maxStorageBufferRange;
        return limits_.storageBufferBytes ? std::min(limits_.storageBufferBytes, device) : device;
    }

    // Largest acceleration-structure buffer: maxMemoryAllocationSize unless a test lowers it.
    uint64_t accelerationLimit() const {
        const uint64_t device = context_.maxBufferBytes;
        return limits_.accelerationBufferBytes ? std::min(limits_.accelerationBufferBytes, device)
                                               : device;
    }

    Expected<VulkanBuffer> uploadArray(const void* data, std::size_t bytes, const char* what,
                                       std::size_t count);

    // The device addresses of what the kernel reads besides the pairs: the patches, and the
    // flat BVH or (ray queries) the acceleration structures, into params and owned buffers.
    Expected<void> uploadScene(const PatchMesh& mesh,
                               const std::vector<shared::PatchGeometry>& patches,
                               PairKernelParams& params, std::vector<VulkanBuffer>& owned,
                               SceneAcceleration& acceleration);

    // The pair kernel specialised to (method constant, level, DAISY_PAIR_MODE_*)
    // (shaders/form_factors.comp.glsl), its ray-query build when `rayQuery`, compiled on first
    // use and kept for the next build. The visibility pass reads neither method nor level, so
    // it has one pipeline whatever they are.
    Expected<const ComputePipeline*> pipeline(int method, int level, int mode, bool rayQuery) {
        if (mode == DAISY_PAIR_MODE_VISIBILITY) {
            method = DAISY_METHOD_HYBRID;
            level = DAISY_DEFAULT_QUADRATURE_LEVEL;
        }
        const std::array<int32_t, 3> constants{method, level, mode};
        const std::tuple key{constants, rayQuery};
        auto found = pipelines_.find(key);
        if (found == pipelines_.end()) {
            const char* shader = rayQuery ? "form_factors.comp/ray_query" : "form_factors.comp";
            const Timer timer;
            auto created = createComputePipeline(context_, embeddedSpirv(shader),
                                                 sizeof(PairKernelParams), constants);
            if (!created) return created.error();
            found = pipelines_.emplace(key, *created).first;
            pipelineSeconds_ += timer.seconds();
            ++pipelinesMade_;
        }
        return &found->second;
    }

    VulkanContext context_;
    VulkanBackendLimits limits_;
    RayTracing rays_;
    bool tracesWithQueries_ = false;  // this build's visibility pass uses ray queries
    std::map<std::tuple<std::array<int32_t, 3>, bool>, ComputePipeline> pipelines_;
    int pipelinesMade_ = 0;  // pipelines created in this build
    double pipelineSeconds_ = 0;  // their creation's wall time in this build
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

Expected<void> VulkanBackend::uploadScene(const PatchMesh& mesh,
                                          const std::vector<shared::PatchGeometry>& patches,
                                          PairKernelParams& params,
                                          std::vector<VulkanBuffer>& owned,
                                          SceneAcceleration& acceleration) {
    auto patchBuffer = uploadArray(patches.data(), patches.size() * sizeof(shared::PatchGeometry),
                                   "patches", patches.size());
    if (!patchBuffer) return patchBuffer.error();
    owned.push_back(*patchBuffer);
    params.patches = patchBuffer->address;
    // The flat BVH either way: the walk traverses it, and its leaf order is the order the
    // acceleration structures get their triangles in (vulkan/acceleration.h says why).
    const Timer timer;
    auto bvh = buildFlatBvh(mesh);
    if (!bvh) return bvh.error();
    const double bvhSeconds = timer.seconds();
    tracesWithQueries_ = rays_.query && !patches.empty();
    if (tracesWithQueries_) {
        auto built = buildSceneAcceleration(context_, bvh->triangles, accelerationLimit());
        if (!built) return built.error();
        acceleration = *built;
        params.scene = acceleration.topAddress;
        logVerbose(
            concat("vulkan: acceleration structures over ", formatCount(acceleration.triangleCount),
                   " triangles: ", formatBytes(double(acceleration.structureBytes)), " (",
                   formatBytes(double(acceleration.buildBytes)),
                   " more during the build), built in ", milliseconds(acceleration.buildSeconds),
                   " (their order, the flat BVH's, in ", milliseconds(bvhSeconds), ")"));
        return {};
    }
    for (const auto& [data, bytes, what, count, address] :
         {std::tuple{static_cast<const void*>(bvh->nodes.data()),
                     bvh->nodes.size() * sizeof(shared::BvhNode), "BVH nodes", bvh->nodes.size(),
                     &params.nodes},
          std::tuple{static_cast<const void*>(bvh->triangles.data()),
                     bvh->triangles.size() * sizeof(shared::BvhTriangle), "BVH triangles",
                     bvh->triangles.size(), &params.triangles}}) {
        auto buffer = uploadArray(data, bytes, what, count);
        if (!buffer) return buffer.error();
        owned.push_back(*buffer);
        *address = buffer->address;
    }
    logVerbose(concat("vulkan: flat BVH over ", formatCount(bvh->triangles.size()),
                      " triangles: ", formatCount(bvh->nodes.size()), " nodes, ",
                      formatBytes(double(bvh->nodes.size() * sizeof(shared::BvhNode) +
                                         bvh->triangles.size() * sizeof(shared::BvhTriangle))),
                      ", built in ", milliseconds(bvhSeconds)));
    return {};
}

Expected<FormFactorResult> VulkanBackend::buildFormFactors(const PatchMesh& mesh,
                                                           const FormFactorSettings& settings) {
    Expected<void> pairMethod = checkPairMethod(settings, name());
    if (!pairMethod) return pairMethod.error();
    const std::vector<shared::PatchGeometry> patches = kernelPatches(mesh);
    std::vector<VulkanBuffer> owned;
    SceneAcceleration acceleration;
    const auto release = [&] {
        for (VulkanBuffer& buffer : owned)
            destroyBuffer(context_, buffer);
        destroySceneAcceleration(context_, acceleration);
    };
    PairKernelParams params{};
    if (auto uploaded = uploadScene(mesh, patches, params, owned, acceleration); !uploaded) {
        release();
        return uploaded.error();
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
    const VulkanBuffer pairBuffer = owned[owned.size() - 2];
    const VulkanBuffer resultBuffer = owned[owned.size() - 1];

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
            auto made =
                backend.pipeline(params.method, params.level, mode, backend.tracesWithQueries_);
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
    GpuPassEvaluator evaluator("vulkan", batchPairs, params.method, passes,
                               context_.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU
                                   ? kCpuDeviceSegmentNs
                                   : kGpuSegmentNs);
    pipelinesMade_ = 0;
    pipelineSeconds_ = 0;
    auto result = computeFormFactors(mesh, settings, evaluator);
    logVerbose(evaluator.summary());
    if (pipelinesMade_ > 0) {
        logVerbose(concat("vulkan: ", pipelinesMade_, " pipeline", pipelinesMade_ > 1 ? "s" : "",
                          " created in ", formatDuration(pipelineSeconds_)));
    }
    release();
    return result;
}

}  // namespace

Expected<std::unique_ptr<Backend>> makeVulkanBackend(const BackendOptions& options,
                                                     const VulkanBackendLimits& limits) {
    auto context = createContext(options.device, options.vulkanRays == VulkanRays::Query);
    if (!context) return context.error();
    RayTracing rays;
    switch (options.vulkanRays) {
        case VulkanRays::Query:
            rays.query = true;
            rays.description = "ray queries (VK_KHR_ray_query; --vulkan-rays query)";
            break;
        case VulkanRays::Software:
            rays.description = "the BVH walk in the shader (--vulkan-rays software)";
            break;
        case VulkanRays::Auto:
            // A CPU implementation's ray queries (lavapipe's) run slower than the walk
            // (docs/performance.md, "GPU backends"); a GPU's run on its ray-tracing hardware.
            rays.query =
                context->rayQuery && context->properties.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU;
            rays.description = rays.query ? "ray queries (VK_KHR_ray_query)"
                : context->rayQuery
                ? "the BVH walk in the shader (faster than this CPU device's ray queries; "
                  "--vulkan-rays query uses them)"
                : "the BVH walk in the shader (the device has no VK_KHR_ray_query)";
            break;
    }
    logVerbose(concat("vulkan: device '", context->properties.deviceName, "' (",
                      deviceTypeName(context->properties.deviceType), ", Vulkan ",
                      VK_API_VERSION_MAJOR(context->properties.apiVersion), ".",
                      VK_API_VERSION_MINOR(context->properties.apiVersion),
                      "), largest storage buffer ",
                      formatBytes(double(context->properties.limits.maxStorageBufferRange)),
                      "; shadow rays: ", rays.description));
    return std::unique_ptr<Backend>(
        std::make_unique<VulkanBackend>(*context, limits, std::move(rays)));
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
