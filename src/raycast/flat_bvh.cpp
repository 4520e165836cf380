#include "raycast/flat_bvh.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <limits>
#include <new>

#include "core/check.h"
#include "core/strings.h"
#include "shared/config.h"

namespace daisy {
namespace {

using shared::BvhNode;
using shared::BvhTriangle;
using shared::vec3;

// The builder's tree, allocated by Embree's thread-local allocator inside the callbacks and freed
// with the RTCBVH. Binary: interior nodes have exactly two children.
struct BuildNode {
    bool leaf = false;
    BuildNode* children[2] = {nullptr, nullptr};  // interior
    uint32_t count = 0;  // leaf: triangles
    uint32_t patches[kFlatBvhMaxLeafSize] = {};  // leaf: patch indices
};

void* createNode(RTCThreadLocalAllocator allocator, unsigned int childCount, void*) {
    DAISY_CHECK_OP(childCount, ==, 2u);
    void* memory = rtcThreadLocalAlloc(allocator, sizeof(BuildNode), alignof(BuildNode));
    return new (memory) BuildNode();
}

void setNodeChildren(void* node, void** children, unsigned int childCount, void*) {
    BuildNode* n = static_cast<BuildNode*>(node);
    for (unsigned int k = 0; k < childCount; ++k)
        n->children[k] = static_cast<BuildNode*>(children[k]);
}

// Boxes are recomputed from the triangles while flattening; Embree's are not kept.
void setNodeBounds(void*, const RTCBounds**, unsigned int, void*) {}

void* createLeaf(RTCThreadLocalAllocator allocator, const RTCBuildPrimitive* primitives,
                 size_t primitiveCount, void*) {
    DAISY_CHECK(primitiveCount >= 1 && primitiveCount <= std::size_t(kFlatBvhMaxLeafSize));
    void* memory = rtcThreadLocalAlloc(allocator, sizeof(BuildNode), alignof(BuildNode));
    BuildNode* n = new (memory) BuildNode();
    n->leaf = true;
    n->count = static_cast<uint32_t>(primitiveCount);
    for (size_t k = 0; k < primitiveCount; ++k)
        n->patches[k] = primitives[k].primID;
    return n;
}

vec3 toFloat(const Vec3d& v) {
    return vec3(static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z));
}

struct Box {
    vec3 lo{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
            std::numeric_limits<float>::infinity()};
    vec3 hi{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
            -std::numeric_limits<float>::infinity()};
    void extend(const vec3& p) {
        lo = vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
        hi = vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
    }
    void extend(const Box& b) {
        extend(b.lo);
        extend(b.hi);
    }
};

// Flattens the subtree of `node` into bvh.nodes[index] (already allocated): a leaf appends its
// triangles; an interior node appends its two children as an adjacent pair, then their subtrees.
// Returns the subtree's box. Recursion depth is the tree depth (<= the builder's maxDepth).
Box flatten(const BuildNode* node, uint32_t index, int depth, const PatchMesh& mesh, FlatBvh& bvh) {
    bvh.depth = std::max(bvh.depth, depth);
    Box box;
    if (node->leaf) {
        const uint32_t first = static_cast<uint32_t>(bvh.triangles.size());
        for (uint32_t k = 0; k < node->count; ++k) {
            const uint32_t p = node->patches[k];
            BvhTriangle t;
            t.a = toFloat(mesh.positions[mesh.patches[p][0]]);
            t.b = toFloat(mesh.positions[mesh.patches[p][1]]);
            t.c = toFloat(mesh.positions[mesh.patches[p][2]]);
            t.patchIndex = p;
            box.extend(t.a);
            box.extend(t.b);
            box.extend(t.c);
            bvh.triangles.push_back(t);
        }
        bvh.nodes[index].first = first;
        bvh.nodes[index].count = node->count;
    } else {
        const uint32_t first = static_cast<uint32_t>(bvh.nodes.size());
        bvh.nodes.resize(bvh.nodes.size() + 2);
        box.extend(flatten(node->children[0], first, depth + 1, mesh, bvh));
        box.extend(flatten(node->children[1], first + 1, depth + 1, mesh, bvh));
        bvh.nodes[index].first = first;
        bvh.nodes[index].count = 0;
    }
    bvh.nodes[index].lo = box.lo;
    bvh.nodes[index].hi = box.hi;
    return box;
}

bool inside(const vec3& p, const BvhNode& n) {
    return p.x >= n.lo.x && p.y >= n.lo.y && p.z >= n.lo.z && p.x <= n.hi.x && p.y <= n.hi.y &&
        p.z <= n.hi.z;
}

}  // namespace

Expected<FlatBvh> buildFlatBvh(const PatchMesh& mesh) {
    FlatBvh bvh;
    const std::size_t n = mesh.patchCount();
    if (n == 0) return bvh;
    if (n > UINT32_MAX / 2) return Error{"too many patches for the flat BVH's 32-bit indices"};

    std::vector<RTCBuildPrimitive> primitives(n);
    for (std::size_t p = 0; p < n; ++p) {
        Box box;
        for (int k = 0; k < 3; ++k)
            box.extend(toFloat(mesh.positions[mesh.patches[p][k]]));
        RTCBuildPrimitive& prim = primitives[p];
        prim.lower_x = box.lo.x, prim.lower_y = box.lo.y, prim.lower_z = box.lo.z;
        prim.upper_x = box.hi.x, prim.upper_y = box.hi.y, prim.upper_z = box.hi.z;
        prim.geomID = 0;
        prim.primID = static_cast<unsigned int>(p);
    }

    RTCDevice device = rtcNewDevice(nullptr);
    if (device == nullptr) return Error{"Embree: cannot create a device for the BVH builder"};
    RTCBVH handle = rtcNewBVH(device);
    RTCBuildArguments args = rtcDefaultBuildArguments();
    // HIGH without a splitPrimitive callback is Embree's full binned SAH build without spatial
    // splits, so every triangle lands in exactly one leaf.
    args.buildQuality = RTC_BUILD_QUALITY_HIGH;
    args.maxBranchingFactor = 2;
    args.maxDepth = DAISY_BVH_STACK_SIZE;
    args.minLeafSize = 1;
    args.maxLeafSize = kFlatBvhMaxLeafSize;
    args.bvh = handle;
    args.primitives = primitives.data();
    args.primitiveCount = n;
    args.primitiveArrayCapacity = n;
    args.createNode = createNode;
    args.setNodeChildren = setNodeChildren;
    args.setNodeBounds = setNodeBounds;
    args.createLeaf = createLeaf;
    args.splitPrimitive = nullptr;
    const BuildNode* root = static_cast<const BuildNode*>(rtcBuildBVH(&args));
    const RTCError error = rtcGetDeviceError(device);
    if (root == nullptr || error != RTC_ERROR_NONE) {
        rtcReleaseBVH(handle);
        rtcReleaseDevice(device);
        return Error{concat("Embree's BVH builder failed (error ", int(error), ") on ", n,
                            " triangles; deeper than ", DAISY_BVH_STACK_SIZE, " levels?")};
    }
    bvh.nodes.reserve(2 * n);
    bvh.triangles.reserve(n);
    bvh.nodes.resize(1);
    flatten(root, 0, 0, mesh, bvh);
    rtcReleaseBVH(handle);
    rtcReleaseDevice(device);
    if (bvh.depth > DAISY_BVH_STACK_SIZE) {
        return Error{concat("the BVH is ", bvh.depth,
                            " levels deep, more than the traversal stack (", DAISY_BVH_STACK_SIZE,
                            ")")};
    }
    return bvh;
}

std::string validateFlatBvh(const FlatBvh& bvh, const PatchMesh& mesh) {
    const std::size_t n = mesh.patchCount();
    if (n == 0)
        return bvh.nodes.empty() && bvh.triangles.empty() ? "" : "non-empty BVH of no patches";
    if (bvh.triangles.size() != n)
        return concat(bvh.triangles.size(), " triangles for ", n, " patches");
    if (bvh.nodes.empty()) return "no nodes";
    std::vector<uint8_t> seenPatch(n, 0);
    std::vector<uint8_t> seenTriangle(n, 0);
    std::vector<uint8_t> seenNode(bvh.nodes.size(), 0);
    // Explicit stack of (node, depth); a node reached twice is a cycle or a shared child.
    std::vector<std::array<uint32_t, 2>> stack = {{0u, 0u}};
    seenNode[0] = 1;
    int depth = 0;
    while (!stack.empty()) {
        const auto [index, level] = stack.back();
        stack.pop_back();
        depth = std::max(depth, int(level));
        const BvhNode& node = bvh.nodes[index];
        if (!(node.lo.x <= node.hi.x && node.lo.y <= node.hi.y && node.lo.z <= node.hi.z)) {
            return concat("node ", index, " has an empty box");
        }
        if (node.count > 0) {
            if (node.count > uint32_t(kFlatBvhMaxLeafSize))
                return concat("leaf ", index, " too big");
            if (uint64_t(node.first) + node.count > n)
                return concat("leaf ", index, " out of range");
            for (uint32_t k = node.first; k < node.first + node.count; ++k) {
                if (seenTriangle[k]++) return concat("triangle ", k, " in two leaves");
                const BvhTriangle& t = bvh.triangles[k];
                if (t.patchIndex >= n) return concat("triangle ", k, " has a bad patch index");
                if (seenPatch[t.patchIndex]++) return concat("patch ", t.patchIndex, " twice");
                const auto& corners = mesh.patches[t.patchIndex];
                const vec3 expected[3] = {toFloat(mesh.positions[corners[0]]),
                                          toFloat(mesh.positions[corners[1]]),
                                          toFloat(mesh.positions[corners[2]])};
                const vec3 actual[3] = {t.a, t.b, t.c};
                for (int c = 0; c < 3; ++c) {
                    if (actual[c].x != expected[c].x || actual[c].y != expected[c].y ||
                        actual[c].z != expected[c].z) {
                        return concat("triangle ", k, " corner ", c, " differs from its patch");
                    }
                    if (!inside(actual[c], node)) return concat("leaf ", index, " misses a corner");
                }
            }
        } else {
            if (uint64_t(node.first) + 1 >= bvh.nodes.size() || node.first <= index) {
                return concat("node ", index, " has children out of range");
            }
            for (uint32_t c = node.first; c <= node.first + 1; ++c) {
                if (seenNode[c]++) return concat("node ", c, " reached twice");
                const BvhNode& child = bvh.nodes[c];
                if (!inside(child.lo, node) || !inside(child.hi, node)) {
                    return concat("node ", c, "'s box is not inside its parent ", index);
                }
                stack.push_back({c, level + 1});
            }
        }
    }
    for (std::size_t k = 0; k < bvh.nodes.size(); ++k) {
        if (!seenNode[k]) return concat("node ", k, " unreachable");
    }
    for (std::size_t p = 0; p < n; ++p) {
        if (!seenPatch[p]) return concat("patch ", p, " missing");
    }
    if (depth != bvh.depth) return concat("depth ", depth, " but recorded ", bvh.depth);
    if (depth > DAISY_BVH_STACK_SIZE) return concat("depth ", depth, " exceeds the stack");
    return "";
}

}  // namespace daisy
