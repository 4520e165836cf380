#pragma once
// The cluster hierarchy of the hierarchical transport (hierarchical/hierarchical_transport.h):
// a binary tree whose leaves are the patches (the finest elements) and whose inner nodes group
// them, so that one link between two nodes can stand for every pair of patches below them
// (clustering: Smits, Arvo and Greenberg 1994, "A clustering algorithm for radiosity in complex
// environments", SIGGRAPH; Sillion 1995, "A unified hierarchical algorithm for global
// illumination with scattering volumes and object clusters", IEEE TVCG 1(3)).
//
// Split rule: top down, a node's patches are cut at the median of the widest of six keys: the
// centroid's x, y, z and the unit normal's x, y, z scaled by half the node's bounding-box
// diagonal. Normal spread thus counts like spatial extent: a wall's front and back patches (a
// double-sided surface) or the two sides of a thin curtain end up in different children once
// the nodes are small, so every node's patches soon face one way (a narrow normal cone), which
// is what lets a link treat the node as one oriented emitter and receiver (the far-field model
// in hierarchical_links.h). The children of one input polygon stay together while they are
// coplanar: a wall subdivided into patches forms a quadtree-like subtree of planar nodes.
//
// Sheltered patches (given per patch: most of a patch's survey rays end within a quarter of its
// size, hierarchical_transport.cpp) part from the open ones first, whatever the keys: a grout
// sheet a few millimetres under floor tiles, the tiles' undersides, a floor's part under a
// block. In one node with the open patches above them they would share its links' visibility,
// sampled over both: the tiles lit by a window sent half their light up, the rest taken as
// blocked by the tiles themselves (a hall's aisle 15-20% darker than the matrix path's).
//
// Nodes are stored in pre-order: a node's children have larger indices than the node, so a
// pass from the last node to the first visits children before parents (pull) and the reverse
// pass parents before children (push). The leaves of node k are order[first .. first + count).
#include <tbb/parallel_invoke.h>

#include <cstdint>
#include <span>
#include <vector>

#include "geometry/patch_mesh.h"
#include "geometry/vec3.h"

namespace daisy {

inline constexpr uint32_t kNoNode = 0xffffffffu;

struct HierarchyNode {
    uint32_t first = 0;  // the node's patches are order[first .. first + count)
    uint32_t count = 0;  // 1: a leaf (a patch)
    uint32_t children[2] = {kNoNode, kNoNode};
    Vec3d boxLo, boxHi;  // bounding box of the patches' corners, scene units
    Vec3d center;  // of the bounding sphere (the bounding box's centre)
    double radius = 0;  // of the bounding sphere: half the box's diagonal
    Vec3d centroid;  // area-weighted centroid of the patches
    // Covariance of an area-uniform point of the node about `centroid` (xx, yy, zz, xy, xz, yz),
    // scene units squared: the second-order term of the far-field coupling.
    double spread[6] = {0, 0, 0, 0, 0, 0};
    double area = 0;  // total patch area, scene units squared
    Vec3d coneAxis;  // unit axis of the cone holding every patch normal
    // cos of the cone's half-angle; -1 when the normals do not fit in a half-space cone
    double coneCos = 1;
    // The box of the patches' unit normals, component by component: a second bound beside the
    // cone, tight where the cone is loose (a strip of a barrel vault: its normals lie on an arc
    // with no component along the barrel, while the cone round them reaches along it).
    Vec3d normalLo, normalHi;
    // The extent of the patches' corners along coneAxis, scene units: for a planar node
    // (isPlanar) the exact range over its corners (lo == hi to rounding when the patches lie in
    // one plane); otherwise the bounding sphere's.
    double slabLo = 0, slabHi = 0;

    bool isLeaf() const { return count == 1; }
    // Every patch normal within 4.5e-5 radians of the axis (the matrix path's coplanarity,
    // radiosity/patch_clusters.h): the node is a (possibly thick) slab of one orientation.
    bool isPlanar() const { return coneCos >= 1 - 1e-9; }
};

struct ClusterTree {
    std::vector<HierarchyNode> nodes;  // pre-order; nodes[0] is the root
    std::vector<uint32_t> order;  // patch indices, each node's a contiguous range
    std::vector<uint32_t> leafOf;  // per patch: its leaf node

    std::size_t bytes() const;
};

// Calls visit(k) once for every node k of `tree`, children before parents (childrenFirst) or
// parents before children: disjoint subtrees in parallel (in pre-order a subtree is a run of
// nodes, 2 count - 1 of them), each of at most serialPatches patches in one loop on one thread.
template <typename Visit>
void visitSubtrees(const ClusterTree& tree, const Visit& visit, bool childrenFirst,
                   uint32_t serialPatches = 4096) {
    if (tree.nodes.empty()) return;
    const auto walk = [&](const auto& self, uint32_t k) -> void {
        const HierarchyNode& node = tree.nodes[k];
        if (node.count <= serialPatches) {
            const std::size_t end = k + 2 * std::size_t(node.count) - 1;
            if (childrenFirst) {
                for (std::size_t i = end; i-- > k;)
                    visit(i);
            } else {
                for (std::size_t i = k; i < end; ++i)
                    visit(i);
            }
            return;
        }
        if (!childrenFirst) visit(k);
        tbb::parallel_invoke([&] { self(self, node.children[0]); },
                             [&] { self(self, node.children[1]); });
        if (childrenFirst) visit(k);
    };
    walk(walk, 0);
}

// Builds the tree over every patch of `mesh` (2 n - 1 nodes for n patches; empty for none),
// in parallel; deterministic (the same tree for any thread count). `sheltered`: per patch, or
// empty (none is).
ClusterTree buildClusterTree(const PatchMesh& mesh, std::span<const uint8_t> sheltered = {});

}  // namespace daisy
