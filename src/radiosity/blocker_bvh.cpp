#include "radiosity/blocker_bvh.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace daisy {

bool inSkipPlane(const ShaftPolygon& polygon, const SkipPlane& plane, double tolerance) {
    if (std::fabs(dot(polygon.normal, plane.normal)) < 1 - 1e-9) return false;
    for (int k = 0; k < polygon.count; ++k) {
        if (std::fabs(dot(plane.normal, polygon.corners[k]) - plane.offset) > tolerance) {
            return false;
        }
    }
    return true;
}

BlockerBvh::BlockerBvh(const std::vector<ShaftPolygon>& blockers) : blockers_(blockers) {
    const auto n = static_cast<uint32_t>(blockers.size());
    order_.resize(n);
    std::iota(order_.begin(), order_.end(), 0u);
    if (n == 0) return;
    std::vector<Vec3d> centres(n);
    for (uint32_t b = 0; b < n; ++b)
        centres[b] = blockers[b].bounds.center();
    nodes_.reserve(2 * (n / kLeafSize + 1));
    build(0, n, centres);
}

uint32_t BlockerBvh::build(uint32_t begin, uint32_t end, const std::vector<Vec3d>& centres) {
    const auto index = static_cast<uint32_t>(nodes_.size());
    nodes_.push_back({});
    Bounds3d bounds, centreBounds;
    for (uint32_t k = begin; k < end; ++k) {
        const Bounds3d& b = blockers_[order_[k]].bounds;
        bounds.extend(b.lo);
        bounds.extend(b.hi);
        centreBounds.extend(centres[order_[k]]);
    }
    nodes_[index].bounds = bounds;
    if (end - begin <= kLeafSize) {
        nodes_[index].first = begin;
        nodes_[index].count = end - begin;
        return index;
    }
    const Vec3d extent = centreBounds.extent();
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
        : extent.y >= extent.z                                    ? 1
                                                                  : 2;
    const uint32_t middle = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                     [&](uint32_t a, uint32_t b) {
                         const double ca = centres[a][axis], cb = centres[b][axis];
                         return ca != cb ? ca < cb : a < b;
                     });
    build(begin, middle, centres);  // the left child directly follows its parent
    const uint32_t right = build(middle, end, centres);
    nodes_[index].first = right;
    nodes_[index].count = 0;
    return index;
}

void BlockerBvh::query(const Shaft& shaft, const SkipPlane& skip0, const SkipPlane& skip1,
                       double tolerance, std::vector<uint32_t>& out, BlockerQueryWork& work) const {
    if (nodes_.empty()) return;
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const uint32_t nodeIndex = stack[--top];
        const Node& node = nodes_[nodeIndex];
        ++work.nodes;
        if (shaft.excludesBox(node.bounds)) continue;
        if (node.count > 0) {
            work.blockers += node.count;
            for (uint32_t k = node.first; k < node.first + node.count; ++k) {
                const uint32_t b = order_[k];
                const ShaftPolygon& polygon = blockers_[b];
                if (inSkipPlane(polygon, skip0, tolerance) ||
                    inSkipPlane(polygon, skip1, tolerance) || shaft.excludesPolygon(polygon)) {
                    continue;
                }
                out.push_back(b);
            }
            continue;
        }
        stack[top++] = node.first;  // right child, visited after the left
        stack[top++] = nodeIndex + 1;
    }
}

}  // namespace daisy
