// The vulkan backend: uploads the patches and the flat BVH once, then for each batch of pairs
// the one driver sends through buildFromPairBatches (backend/pair_batches.h: only the pairs no
// culling decided; clear-shaft pairs without rays) uploads the pairs, runs
// shaders/form_factors.comp.glsl over them in dispatches short enough for a display watchdog, and
// downloads the factors: pairs with rays in two passes, V first and then the quadrature for the
// pairs some segment gets through, each pass a pipeline specialised to the method, level and mode
// (docs/backends.md); the hybrid quadrature itself in two, without the adaptive refinement and
// then with it for the pairs that have a near cell. Every buffer stays within the device's
// maxStorageBufferRange (128 MiB on lavapipe): batches are sized to it, and a scene whose patch
// or BVH arrays exceed it is refused.
#include "vulkan/vulkan_backend.h"

#include <algorithm>
#include <array>
#include <map>
#include <tuple>
#include <vector>

#include "backend/pair_batches.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/strings.h"
#include "core/timer.h"
#include "radiosity/form_factors_internal.h"
#include "radiosity/pair_evaluator.h"
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
    const ComputePipeline& pipeline(int method, int level, int mode) {
        const std::array<int32_t, 3> key{method, level, mode};
        auto found = pipelines_.find(key);
        if (found == pipelines_.end()) {
            found = pipelines_
                        .emplace(key,
                                 createComputePipeline(context_, embeddedSpirv("form_factors.comp"),
                                                       sizeof(PairKernelParams), key))
                        .first;
        }
        return found->second;
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
    VulkanBuffer buffer = createBuffer(context_, std::max<std::size_t>(bytes, 64));
    upload(context_, buffer, data, bytes);
    return buffer;
}

Expected<FormFactorResult> VulkanBackend::buildFormFactors(const PatchMesh& mesh,
                                                           const FormFactorSettings& settings) {
    if (settings.method == FormFactorMethod::Stochastic) {
        return Error{
            "--method stochastic is not a pair method: the vulkan backend computes "
            "riemann, nusselt and hybrid (use --backend cpu for stochastic)"};
    }
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
        : std::max<uint64_t>(DAISY_PAIR_WORKGROUP_SIZE,
                             kDispatchWork / pairWork(settings) / DAISY_PAIR_WORKGROUP_SIZE *
                                 DAISY_PAIR_WORKGROUP_SIZE);
    dispatchPairs = std::min(dispatchPairs, groupLimit);

    VulkanBuffer pairBuffer = createBuffer(context_, batchPairs * sizeof(PairIndex));
    VulkanBuffer resultBuffer = createBuffer(context_, batchPairs * sizeof(PairFactors));
    owned.push_back(pairBuffer);
    owned.push_back(resultBuffer);

    PairKernelParams params{};
    params.patches = owned[0].address;
    params.nodes = owned[1].address;
    params.triangles = owned[2].address;
    params.pairs = pairBuffer.address;
    params.results = resultBuffer.address;
    params.method = detail::methodConstant(settings.method);
    params.level = settings.quadratureLevel;
    params.seed = detail::seed32(settings.seed);  // as the cpu and reference backends fold it
    params.clearance = kEndClearanceRelative;

    // Runs the kernel in `mode` over pairs (at most batchPairs) into out.
    const auto run = [&](std::span<const PairIndex> pairs, int mode, std::span<PairFactors> out) {
        const ComputePipeline& kernel = pipeline(params.method, params.level, mode);
        upload(context_, pairBuffer, pairs.data(), pairs.size_bytes());
        for (std::size_t first = 0; first < pairs.size(); first += dispatchPairs) {
            params.pairOffset = uint32_t(first);
            params.pairCount = uint32_t(std::min<uint64_t>(dispatchPairs, pairs.size() - first));
            const uint32_t groups =
                (params.pairCount + DAISY_PAIR_WORKGROUP_SIZE - 1) / DAISY_PAIR_WORKGROUP_SIZE;
            // One submission per dispatch: a watchdog sees one short job at a time.
            submitAndWait(context_, [&](VkCommandBuffer commands) {
                vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.pipeline);
                vkCmdPushConstants(commands, kernel.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                                   sizeof params, &params);
                vkCmdDispatch(commands, groups, 1, 1);
                VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
                barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
                barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
                vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                     VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                                     1, &barrier, 0, nullptr, 0, nullptr);
            });
        }
        download(context_, resultBuffer, out.data(), out.size_bytes());
    };
    // The unoccluded factors of pairs into out. Hybrid: every pair through the pipeline without
    // the refinement first (DAISY_PAIR_MODE_FAR_FIELD), then those it marks as having a near cell
    // through the whole kernel; the same factors as the whole kernel on every pair, bit for bit
    // (shared/pair_kernel.h, pairEntryFarField).
    std::vector<PairIndex> near;
    std::vector<uint32_t> nearSlot;
    std::vector<PairFactors> nearFactors;
    uint64_t nearPairs = 0;
    const auto runFactors = [&](std::span<const PairIndex> pairs, std::span<PairFactors> out) {
        if (params.method != DAISY_METHOD_HYBRID) {
            run(pairs, DAISY_PAIR_MODE_FACTORS, out);
            return;
        }
        run(pairs, DAISY_PAIR_MODE_FAR_FIELD, out);
        near.clear();
        nearSlot.clear();
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            if (out[k].fij == DAISY_FF_NEEDS_NEAR_CELLS) {
                near.push_back(pairs[k]);
                nearSlot.push_back(uint32_t(k));
            }
        }
        nearPairs += near.size();
        if (near.empty()) return;
        nearFactors.resize(near.size());
        run(near, DAISY_PAIR_MODE_FACTORS, nearFactors);
        for (std::size_t k = 0; k < near.size(); ++k)
            out[nearSlot[k]] = nearFactors[k];
    };
    // Pairs with rays: V_ij first, then the quadrature only for the pairs some ray reaches, and
    // F = factor * V in float, as pairEntry rounds it (shared/pair_kernel.h).
    std::vector<PairFactors> visibility, factors;
    std::vector<PairIndex> open;
    std::vector<uint32_t> openSlot;
    double factorSeconds = 0, visibilitySeconds = 0;
    uint64_t tracedPairs = 0, openPairs = 0, factorPairs = 0;
    const PairKernelBatch evaluate = [&](std::span<const PairIndex> pairs, int rays,
                                         std::span<PairFactors> out) -> Expected<void> {
        params.rays = rays;
        if (rays == 0) {
            const auto start = Clock::now();
            runFactors(pairs, out);
            factorPairs += pairs.size();
            factorSeconds += secondsSince(start);
            return {};
        }
        auto start = Clock::now();
        visibility.resize(pairs.size());
        run(pairs, DAISY_PAIR_MODE_VISIBILITY, visibility);
        visibilitySeconds += secondsSince(start);
        open.clear();
        openSlot.clear();
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            out[k] = PairFactors{0.0f, 0.0f};
            if (visibility[k].fij > 0.0f) {
                open.push_back(pairs[k]);
                openSlot.push_back(uint32_t(k));
            }
        }
        tracedPairs += pairs.size();
        openPairs += open.size();
        if (open.empty()) return {};
        start = Clock::now();
        factors.resize(open.size());
        runFactors(open, factors);
        factorPairs += open.size();
        for (std::size_t k = 0; k < open.size(); ++k) {
            const float v = visibility[openSlot[k]].fij;
            out[openSlot[k]] = PairFactors{factors[k].fij * v, factors[k].fji * v};
        }
        factorSeconds += secondsSince(start);
        return {};
    };
    auto result = buildFromPairBatches(mesh, settings, "vulkan", batchPairs, evaluate);
    logVerbose(concat("vulkan: ", formatCount(tracedPairs), " traced pairs' visibility in ",
                      formatDuration(visibilitySeconds), ", the factors of ",
                      formatCount(openPairs), " of them and of every clear pair in ",
                      formatDuration(factorSeconds), " (", formatCount(nearPairs), " of those ",
                      formatCount(factorPairs), " with a near cell, whose factors are the whole ",
                      "hybrid kernel's; the others' without its refinement)"));
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
