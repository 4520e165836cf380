#pragma once
// The one scene model every loader fills: world-space triangles in scene order with a material
// per triangle, the materials, and the cameras. Units are the file's (glTF: metres).
#include <cstddef>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "scene/material.h"

namespace daisy {

// A perspective camera in world space. Looks along `forward` with `up` as the image's up.
struct Camera {
    std::string name;
    Vec3d position;
    Vec3d forward{0, 0, -1};  // unit
    Vec3d up{0, 1, 0};  // unit, orthogonal to forward
    double yFovRad = 0.8;  // vertical field of view, radians
    double aspectRatio = 0;  // width / height; 0 = take it from the image size
    double zNear = 0.01;
    double zFar = 0;  // 0 = infinite
};

struct Scene {
    std::string path;  // the file it was loaded from
    TriangleMesh mesh;
    std::vector<Material> materials;
    std::vector<Camera> cameras;
    std::size_t degenerateDropped = 0;  // zero-area triangles removed on load
    std::vector<std::string> warnings;  // printed by the caller
};

}  // namespace daisy
