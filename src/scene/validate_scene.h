#pragma once
// Checks a freshly loaded scene and drops degenerate triangles. Errors (returned, naming
// scene.path and the place): non-finite positions, indices out of range, material indices out
// of range, RGB reflectance components outside [0, 1], negative or non-finite emission.
// Zero-area triangles (area <= 1e-14 x longest edge squared) are removed, counted in
// scene.degenerateDropped, and reported in scene.warnings. Also fails on a scene with no
// triangles left.
#include "core/expected.h"
#include "scene/scene.h"

namespace daisy {

Expected<void> validateScene(Scene& scene);

}  // namespace daisy
