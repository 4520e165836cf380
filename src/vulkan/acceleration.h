#pragma once
// Acceleration structures for the vulkan backend's ray queries (VK_KHR_acceleration_structure,
// GL_EXT_ray_query): one bottom-level structure over a triangle list (float corners, opaque, both
// faces hit, triangle k its primitive k) and one top-level structure holding it once with the
// identity transform, built on the device in one submission (PREFER_FAST_TRACE). The triangles
// are the flat BVH's (raycast/flat_bvh.h: the kernels' float corners) in its leaf order: a
// driver may build its tree in the order it is given (lavapipe halves the primitive list by
// count, with no spatial sort), so a spatially coherent order is what makes its tree good; the
// SAH tree's leaf order is one. Only the two structures stay allocated: the corners, the
// instance and the scratch buffer are released once the build is done.
#include <volk.h>

#include <cstdint>
#include <span>

#include "core/expected.h"
#include "shared/gpu_types.h"
#include "vulkan/buffers.h"
#include "vulkan/context.h"

namespace daisy {

struct SceneAcceleration {
    VulkanBuffer bottomBuffer;
    VulkanBuffer topBuffer;
    VkAccelerationStructureKHR bottom = VK_NULL_HANDLE;
    VkAccelerationStructureKHR top = VK_NULL_HANDLE;
    VkDeviceAddress topAddress = 0;  // what the shader's accelerationStructureEXT(uint64_t) takes
    uint64_t triangleCount = 0;
    uint64_t structureBytes = 0;  // both structures, bytes (what stays allocated)
    uint64_t buildBytes = 0;  // the corners, the instance and the scratch during the build, bytes
    double buildSeconds = 0;  // wall time of the size queries, uploads and the device build
};

// Builds the structures over `triangles` (their corners a, b, c, in this order). The context
// must have ray queries enabled (VulkanContext::rayQuery). `bufferLimitBytes` caps every
// buffer (the device's maxMemoryAllocationSize unless a test lowers it). Errors: a triangle
// count over maxPrimitiveCount, or a structure, scratch or corner buffer over the buffer limit
// (each naming the limit and the device, and what to use instead), or a failed Vulkan call;
// nothing is left allocated then.
Expected<SceneAcceleration> buildSceneAcceleration(const VulkanContext& context,
                                                   std::span<const shared::BvhTriangle> triangles,
                                                   uint64_t bufferLimitBytes);
void destroySceneAcceleration(const VulkanContext& context, SceneAcceleration& acceleration);

}  // namespace daisy
