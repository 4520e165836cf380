#pragma once
// Checks a freshly loaded scene and drops degenerate triangles. Errors (returned, naming
// scene.path and the place): non-finite positions, indices out of range, material indices out
// of range, RGB reflectance components outside [0, 1], negative or non-finite emission.
// Zero-area triangles (area <= 1e-14 x longest edge squared) are removed, counted in
// scene.degenerateDropped, and reported in scene.warnings. Also fails on a scene with no
// triangles left, on geometry or cameras float32 ray tracing cannot represent
// (checkRayTracingRange), and on emission that would overflow the solve; warns when nothing
// emits light (noEmitterWarning).
#include <string>

#include "core/expected.h"
#include "scene/scene.h"

namespace daisy {

Expected<void> validateScene(Scene& scene);

// The limits of float32 geometry (form-factor kernels, the ray caster, GPU backends), measured on
// the Cornell box scaled by powers of ten: factors are exact up to a 5e8 m scene and from a
// 5e-10 m one, and wrong (inf, zero rows) from 5e9 m and at 5e-11 m; the limits keep a factor
// of 5 to 50 from both. A scene may not lie further from the origin than kMaxOffsetRatio times
// its size (float32 spacing there is 6e-3 of the scene), nor a camera from its centre.
inline constexpr double kMaxSceneCoordinate = 1e8;
inline constexpr double kMinSceneDiagonal = 1e-8;
inline constexpr double kMaxOffsetRatio = 1e5;

struct SceneExtent {
    Vec3d low, high;  // bounding box of the triangles' corners
    double diagonal = 0;
    double largestCoordinate = 0;  // max |x|, |y|, |z| over those corners
};
SceneExtent sceneExtent(const TriangleMesh& mesh);

// Refuses geometry and cameras outside the limits above, naming the extent and the limit. Runs
// inside validateScene; call it again after moving cameras or geometry.
Expected<void> checkRayTracingRange(const Scene& scene);

// "<file>: no surface emits light ...", or "" when some triangle's material emits. validateScene
// adds it to scene.warnings; front ends print it.
std::string noEmitterWarning(const Scene& scene);

}  // namespace daisy
