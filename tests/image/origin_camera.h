#pragma once
// The cameras the image and render tests share.
#include <string>

#include "image/camera.h"

namespace daisy::test {

// A camera at the origin looking along -z, 60 degree vertical field of view.
inline Camera originCamera() {
    Camera camera;
    camera.position = {0, 0, 0};
    camera.forward = {0, 0, -1};
    camera.up = {0, 1, 0};
    camera.yFovRad = 1.0471975511965976;
    return camera;
}

// A camera named `name` at `from` looking at `to`, `up` the scene's up direction (not parallel
// to the view), vertical field of view `yFovRad`.
inline Camera lookAtCamera(const std::string& name, Vec3d from, Vec3d to, Vec3d up,
                           double yFovRad) {
    Camera camera;
    camera.name = name;
    camera.position = from;
    camera.forward = normalize(to - from);
    const Vec3d side = normalize(cross(camera.forward, up));
    camera.up = cross(side, camera.forward);
    camera.yFovRad = yFovRad;
    return camera;
}

}  // namespace daisy::test
