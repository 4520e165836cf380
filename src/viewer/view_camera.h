#pragma once
// The viewer's camera: a daisy::Camera (scene/scene.h, the same pinhole that
// `daisy render` shoots primary rays through, image/camera.h) moved by orbit, pan, dolly and fly
// controls, and its Vulkan clip-from-world matrix. Up is kept at +y (the glTF convention) once the
// user moves a camera; a glTF camera's own up is used until then.
#include <array>
#include <cstdint>
#include <optional>

#include "geometry/patch_mesh.h"
#include "geometry/vec3.h"
#include "scene/scene.h"

namespace daisy::viewer {

class ViewCamera {
public:
    // Starts at `camera`, orbiting the point `orbitDistance` (scene units, > 0) ahead of it.
    ViewCamera(const Camera& camera, double orbitDistance);

    const Camera& camera() const { return camera_; }
    Vec3d target() const { return camera_.position + camera_.forward * distance_; }
    double orbitDistance() const { return distance_; }

    // Turns the camera about the target: yaw about +y, pitch about the camera's right axis
    // (radians; pitch stops 1 degree short of straight up or down).
    void orbit(double yawRad, double pitchRad);
    // Turns the camera about its own position (fly mode's mouse look); same angles as orbit.
    void look(double yawRad, double pitchRad);
    // Moves camera and target along the camera's right and up axes (scene units).
    void pan(double right, double up);
    // Moves the camera towards the target by `factor` of the distance (0.1 = 10% closer; negative
    // moves away); the target stays.
    void dolly(double factor);
    // Moves camera and target: `forward` along the view direction, `right`, `up` along +y.
    void fly(double forward, double right, double up);

private:
    void setForward(const Vec3d& forward);
    Camera camera_;
    double distance_;
};

// The Vulkan clip-from-world matrix (column-major) of `camera` for an image of aspect
// width / height: x right, y down (Vulkan), reverse-Z with an infinite far plane (depth =
// zNear / view depth, so nearer is larger; compare GREATER, clear 0). A world point that
// primaryRay(camera, w, h, x, y) passes through projects to pixel (x, y).
std::array<float, 16> viewProjection(const Camera& camera, double aspect);

// The distance to orbit about for `camera` in a scene whose bounding box is [lo, hi]: the
// distance along the view direction to the box centre's projection, at least 1% of its diagonal.
double defaultOrbitDistance(const Camera& camera, const Vec3d& lo, const Vec3d& hi);

// "Frame all": `camera` moved back along its own view direction until the bounding sphere of
// [lo, hi] fits both fields of view at `aspect` (width / height), looking at the box centre; the
// orbit distance is the distance to that centre. The viewer's start for scenes without cameras
// (outside the geometry) and its Home key.
struct Framing {
    Camera camera;
    double orbitDistance = 1;
};
Framing frameAll(const Camera& camera, const Vec3d& lo, const Vec3d& hi, double aspect);

// The patch seen through image position (x, y) (pixels, as primaryRay) of a width x height view,
// the nearest hit of the primary ray (brute force over the patches with the shared watertight
// test, src/shared/intersect.h: fine for a click); nullopt when the ray misses.
std::optional<uint32_t> pickPatch(const PatchMesh& mesh, const Camera& camera, int width,
                                  int height, double x, double y);

}  // namespace daisy::viewer
