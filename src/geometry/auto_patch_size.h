#pragma once
// The patch size `daisy render` and `daisy view` use when --subdivide is not given.
//
// Rule: a patch budget of max(kAutoPatchBudget, T) patches for a scene of T triangles, and the
// smallest maximum edge length whose patch count fits it, found by bisection on a log scale
// between the longest edge and 2^-20 of it (counting by subdividing, which stops as soon as it
// passes the budget), then rounded up to 3 significant digits (so `--subdivide <that value>`
// reproduces it). Subdivision splits the
// longest edges first, so large triangles (the measured Cornell box's two-triangle walls) become
// patches of about equal size while small ones are kept. A scene of T >= kAutoPatchBudget
// triangles is kept as it is (maxEdge 0): it is already as fine as the budget allows.
//
// Cost: the view factors cost O(n^2) in the patch count n, so the budget caps the automatic
// mesh at the cost of a 4,096-patch scene, or of the scene's own triangles when it has more
// (docs/rendering.md gives the measured times). Choosing the size itself costs ~25 trial
// subdivisions of at most the budget each: a few milliseconds.
#include <cstdint>

#include "geometry/mesh.h"

namespace daisy {

// Patches the automatic mesh aims at when the scene has fewer triangles: about 8.4 million
// patch pairs, a few seconds of view factors on two cores (docs/rendering.md).
inline constexpr uint64_t kAutoPatchBudget = 4096;

struct AutoPatchSize {
    double maxEdge = 0;  // scene units; 0 = keep the input triangles
    uint64_t budget = 0;  // patches allowed: max(kAutoPatchBudget, triangle count)
    uint64_t patches = 0;  // the patch count at maxEdge, <= budget
};

// Chooses the patch size for `mesh` under `budget` patches (the default is the rule above; a
// budget below the triangle count keeps the triangles). An empty mesh gives maxEdge 0.
AutoPatchSize chooseAutoPatchSize(const TriangleMesh& mesh, uint64_t budget = 0);

}  // namespace daisy
