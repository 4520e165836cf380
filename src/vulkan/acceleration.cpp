#include "vulkan/acceleration.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "core/check.h"
#include "core/strings.h"
#include "core/timer.h"
#include "vulkan/vk_check.h"

namespace daisy {
namespace {

constexpr VkBufferUsageFlags kBuildInput =
    VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR;
constexpr VkBufferUsageFlags kStructureStorage =
    VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR;

// One level's build description; `geometry` is referenced by `info`, so the struct stays put.
struct LevelBuild {
    VkAccelerationStructureGeometryKHR geometry{
        VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
    VkAccelerationStructureBuildGeometryInfoKHR info{
        VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
    VkAccelerationStructureBuildSizesInfoKHR sizes{
        VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
    uint32_t primitiveCount = 0;

    LevelBuild(const LevelBuild&) = delete;
    LevelBuild& operator=(const LevelBuild&) = delete;
    LevelBuild(VkAccelerationStructureTypeKHR type, uint32_t count) : primitiveCount(count) {
        info.type = type;
        info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
        info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
        info.geometryCount = 1;
        info.pGeometries = &geometry;
        geometry.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
    }

    // The sizes for primitiveCount (addresses may still be 0: they do not change the sizes).
    void querySizes(const VulkanContext& context) {
        vkGetAccelerationStructureBuildSizesKHR(context.device,
                                                VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR,
                                                &info, &primitiveCount, &sizes);
    }
};

void setTriangles(LevelBuild& level, VkDeviceAddress corners, uint64_t triangleCount) {
    level.geometry.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
    VkAccelerationStructureGeometryTrianglesDataKHR& triangles = level.geometry.geometry.triangles;
    triangles.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
    triangles.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
    triangles.vertexData.deviceAddress = corners;
    triangles.vertexStride = 3 * sizeof(float);
    triangles.maxVertex = uint32_t(3 * triangleCount - 1);
    triangles.indexType = VK_INDEX_TYPE_NONE_KHR;
}

void setInstances(LevelBuild& level, VkDeviceAddress instances) {
    level.geometry.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
    VkAccelerationStructureGeometryInstancesDataKHR& data = level.geometry.geometry.instances;
    data.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
    data.arrayOfPointers = VK_FALSE;
    data.data.deviceAddress = instances;
}

VkDeviceAddress structureAddress(const VulkanContext& context,
                                 VkAccelerationStructureKHR structure) {
    VkAccelerationStructureDeviceAddressInfoKHR info{
        VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
    info.accelerationStructure = structure;
    return vkGetAccelerationStructureDeviceAddressKHR(context.device, &info);
}

// A structure of `level`'s size in a buffer of its own, into `buffer` and `structure`.
Expected<void> createStructure(const VulkanContext& context, const LevelBuild& level,
                               VulkanBuffer& buffer, VkAccelerationStructureKHR& structure) {
    auto made = createBuffer(context, level.sizes.accelerationStructureSize, kStructureStorage);
    if (!made) return made.error();
    buffer = *made;
    VkAccelerationStructureCreateInfoKHR info{
        VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
    info.buffer = buffer.buffer;
    info.size = level.sizes.accelerationStructureSize;
    info.type = level.info.type;
    VK_CHECK(vkCreateAccelerationStructureKHR(context.device, &info, nullptr, &structure));
    return {};
}

// A barrier after an acceleration-structure build, before `stage` reads what it wrote with
// `access` (the next build reusing the scratch, or the compute shaders' ray queries).
void buildBarrier(VkCommandBuffer commands, VkPipelineStageFlags stage, VkAccessFlags access) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
    barrier.dstAccessMask = access;
    vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, stage, 0,
                         1, &barrier, 0, nullptr, 0, nullptr);
}

// The error for a buffer of `bytes` over `limit`, naming what it is for.
Error overLimit(const VulkanContext& context, const char* what, uint64_t bytes, uint64_t limit,
                uint64_t triangles) {
    return Error{concat(
        "the vulkan backend's ray queries need ", what, " of ", formatBytes(double(bytes)), " for ",
        formatCount(triangles), " triangles, more than this device's buffer limit of ",
        formatBytes(double(limit)), " (maxMemoryAllocationSize on '", context.properties.deviceName,
        "'); use --vulkan-rays software, a larger --subdivide or --backend cpu")};
}

Expected<void> build(const VulkanContext& context, std::span<const shared::BvhTriangle> triangles,
                     uint64_t bufferLimit, SceneAcceleration& result,
                     std::vector<VulkanBuffer>& temporaries) {
    const VkPhysicalDeviceAccelerationStructurePropertiesKHR& limits =
        context.accelerationProperties;
    const uint64_t count = triangles.size();
    if (count > limits.maxPrimitiveCount || limits.maxGeometryCount < 1 ||
        limits.maxInstanceCount < 1) {
        return Error{
            concat("the vulkan backend's ray queries need one acceleration structure "
                   "over ",
                   formatCount(count),
                   " triangles, more than this device's "
                   "maxPrimitiveCount of ",
                   formatCount(limits.maxPrimitiveCount), " ('", context.properties.deviceName,
                   "'); use --vulkan-rays software, a larger --subdivide or --backend "
                   "cpu")};
    }
    LevelBuild bottom(VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, uint32_t(count));
    setTriangles(bottom, 0, count);
    bottom.querySizes(context);
    LevelBuild top(VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, 1);
    setInstances(top, 0);
    top.querySizes(context);
    const uint64_t alignment =
        std::max<uint64_t>(limits.minAccelerationStructureScratchOffsetAlignment, 1);
    const uint64_t scratchBytes =
        std::max(bottom.sizes.buildScratchSize, top.sizes.buildScratchSize) + alignment;
    const uint64_t cornerBytes = count * 9 * sizeof(float);
    for (const auto& [what, bytes] :
         {std::pair{"a bottom-level acceleration structure",
                    bottom.sizes.accelerationStructureSize},
          std::pair{"a top-level acceleration structure", top.sizes.accelerationStructureSize},
          std::pair{"a build scratch buffer", scratchBytes},
          std::pair{"a buffer of triangle corners", cornerBytes}}) {
        if (bytes > bufferLimit) return overLimit(context, what, bytes, bufferLimit, count);
    }

    std::vector<float> corners;
    corners.reserve(count * 9);
    for (const shared::BvhTriangle& t : triangles) {
        for (const shared::vec3& p : {t.a, t.b, t.c})
            corners.insert(corners.end(), {p.x, p.y, p.z});
    }
    auto cornerBuffer = createBuffer(context, cornerBytes, kBuildInput);
    if (!cornerBuffer) return cornerBuffer.error();
    temporaries.push_back(*cornerBuffer);
    if (auto uploaded = upload(context, *cornerBuffer, corners.data(), cornerBytes); !uploaded)
        return uploaded;
    auto scratch = createBuffer(context, scratchBytes);
    if (!scratch) return scratch.error();
    temporaries.push_back(*scratch);
    const VkDeviceAddress scratchAddress =
        (scratch->address + alignment - 1) / alignment * alignment;

    if (auto made = createStructure(context, bottom, result.bottomBuffer, result.bottom); !made)
        return made;
    if (auto made = createStructure(context, top, result.topBuffer, result.top); !made) return made;

    VkAccelerationStructureInstanceKHR instance{};
    instance.transform.matrix[0][0] = 1.0f;
    instance.transform.matrix[1][1] = 1.0f;
    instance.transform.matrix[2][2] = 1.0f;
    instance.mask = 0xff;
    instance.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;
    instance.accelerationStructureReference = structureAddress(context, result.bottom);
    auto instanceBuffer = createBuffer(context, sizeof instance, kBuildInput);
    if (!instanceBuffer) return instanceBuffer.error();
    temporaries.push_back(*instanceBuffer);
    if (auto uploaded = upload(context, *instanceBuffer, &instance, sizeof instance); !uploaded)
        return uploaded;

    setTriangles(bottom, cornerBuffer->address, count);
    bottom.info.dstAccelerationStructure = result.bottom;
    bottom.info.scratchData.deviceAddress = scratchAddress;
    setInstances(top, instanceBuffer->address);
    top.info.dstAccelerationStructure = result.top;
    top.info.scratchData.deviceAddress = scratchAddress;
    auto built = submitAndWait(context, [&](VkCommandBuffer commands) {
        for (LevelBuild* level : {&bottom, &top}) {
            VkAccelerationStructureBuildRangeInfoKHR range{};
            range.primitiveCount = level->primitiveCount;
            const VkAccelerationStructureBuildRangeInfoKHR* ranges = &range;
            vkCmdBuildAccelerationStructuresKHR(commands, 1, &level->info, &ranges);
            // The top level reads the bottom one and reuses the scratch; the shaders read both.
            if (level == &bottom) {
                buildBarrier(commands, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                             VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR |
                                 VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR);
            } else {
                buildBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                             VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR);
            }
        }
    });
    if (!built) return built;
    result.topAddress = structureAddress(context, result.top);
    result.triangleCount = count;
    result.structureBytes =
        bottom.sizes.accelerationStructureSize + top.sizes.accelerationStructureSize;
    result.buildBytes = cornerBytes + sizeof instance + scratchBytes;
    return {};
}

}  // namespace

Expected<SceneAcceleration> buildSceneAcceleration(const VulkanContext& context,
                                                   std::span<const shared::BvhTriangle> triangles,
                                                   uint64_t bufferLimitBytes) {
    DAISY_CHECK(context.rayQuery);
    DAISY_CHECK(!triangles.empty());
    const Timer timer;
    SceneAcceleration result;
    std::vector<VulkanBuffer> temporaries;
    auto built = build(context, triangles, bufferLimitBytes, result, temporaries);
    for (VulkanBuffer& buffer : temporaries)
        destroyBuffer(context, buffer);
    if (!built) {
        destroySceneAcceleration(context, result);
        return built.error();
    }
    result.buildSeconds = timer.seconds();
    return result;
}

void destroySceneAcceleration(const VulkanContext& context, SceneAcceleration& acceleration) {
    if (acceleration.top)
        vkDestroyAccelerationStructureKHR(context.device, acceleration.top, nullptr);
    if (acceleration.bottom)
        vkDestroyAccelerationStructureKHR(context.device, acceleration.bottom, nullptr);
    destroyBuffer(context, acceleration.topBuffer);
    destroyBuffer(context, acceleration.bottomBuffer);
    acceleration = SceneAcceleration{};
}

}  // namespace daisy
