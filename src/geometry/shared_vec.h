#pragma once
// The mesh's double-precision vectors as the shared kernels' float vec3 (shared/prelude.h):
// what every CPU caller of a src/shared/ function hands it.
#include "geometry/vec3.h"
#include "shared/prelude.h"

namespace daisy {

inline shared::vec3 toVec3(const Vec3d& v) {
    return {float(v.x), float(v.y), float(v.z)};
}

}  // namespace daisy
