#include "geometry/auto_patch_size.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "geometry/subdivision.h"

namespace daisy {
namespace {

double longestEdge(const TriangleMesh& mesh) {
    double longest = 0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        for (int k = 0; k < 3; ++k) {
            longest = std::max(longest, length(mesh.corner(t, (k + 1) % 3) - mesh.corner(t, k)));
        }
    }
    return longest;
}

// The double that "%.3g" of `value` rounded up prints as, so the printed size is the size used.
double roundUpTo3Digits(double value) {
    const double unit = std::pow(10.0, std::floor(std::log10(value)) - 2);
    char text[32];
    std::snprintf(text, sizeof(text), "%.3g", std::ceil(value / unit * (1 - 1e-12)) * unit);
    return std::strtod(text, nullptr);
}

}  // namespace

AutoPatchSize chooseAutoPatchSize(const TriangleMesh& mesh, uint64_t budget) {
    AutoPatchSize out;
    const uint64_t triangles = mesh.triangleCount();
    out.budget = budget > 0 ? budget : std::max<uint64_t>(kAutoPatchBudget, triangles);
    out.patches = triangles;
    const double longest = longestEdge(mesh);
    if (triangles == 0 || triangles >= out.budget || !(longest > 0)) return out;

    // The patch count of a size, or 0 when it exceeds the budget: the subdivision itself, which
    // stops as soon as it passes the budget (estimatePatchCount's bound is several times too
    // high for slivers, so it would choose sizes far coarser than the budget allows).
    std::vector<Vec3d> positions;
    std::vector<std::array<uint32_t, 3>> welded(triangles);
    const auto count = [&](double maxEdge) -> uint64_t {
        positions.clear();
        VertexWelder welder(positions);
        for (std::size_t t = 0; t < triangles; ++t) {
            for (int k = 0; k < 3; ++k)
                welded[t][k] = welder.insert(mesh.corner(t, k));
        }
        auto refined = bisectLongestEdges(welded, maxEdge, out.budget, welder);
        return refined ? refined->triangles.size() : 0;
    };
    // The count is non-increasing in maxEdge; keep count(hi) > 0 and count(lo) == 0.
    double hi = longest, lo = longest * 0x1p-20;
    if (count(lo) > 0) {
        hi = lo;
    } else {
        for (int step = 0; step < 40 && hi / lo > 1.001; ++step) {
            const double mid = std::sqrt(lo * hi);
            (count(mid) > 0 ? hi : lo) = mid;
        }
    }
    const double maxEdge = roundUpTo3Digits(hi);
    if (maxEdge >= longest) return out;  // nothing would be split
    out.maxEdge = maxEdge;
    out.patches = count(maxEdge);
    return out;
}

}  // namespace daisy
