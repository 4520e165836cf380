#pragma once
// The camera the image tests share.
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

}  // namespace daisy::test
