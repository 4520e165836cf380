#pragma once
// Choosing the camera of a render (DESIGN.md section 7): a glTF camera by name or index,
// else the scene's first camera, else an automatic framing; and primary rays through pixels.
#include <string>

#include "core/expected.h"
#include "raycast/ray.h"
#include "scene/scene.h"

namespace daisy {

// `selector` is a camera name (exact match first), or a 0-based index into the file's camera
// list (Camera::fileIndex: glTF cameras[], in file order; for cameras without one, their order
// in scene.cameras); a skipped (orthographic) camera's index is refused naming why;
// empty = the first camera, or frameScene(scene, aspectRatio) when the scene has none. Error
// (naming scene.path and listing the cameras it has) when the selector matches nothing.
// aspectRatio (width / height of the image) is only used by the automatic framing.
Expected<Camera> chooseCamera(const Scene& scene, const std::string& selector,
                              double aspectRatio = 1.0);

// Automatic framing. Up is +y (the glTF convention) and the camera looks horizontally at the
// box centre. Inside a closed room the preferred view direction is -z when the bounding box is
// at least as wide in x as deep in z, else -x, so the camera faces the larger pair of vertical
// box faces; an open scene prefers the front, +z (glTF models face +z).
// - Closed scene (a room): rays from the box centre in the 26 axis, edge and corner directions
//   all hit a triangle, and most of the farthest hits face the centre. The camera stands inside,
//   looking along the preferred direction from the centre of the box face behind it, pulled in
//   by 2% of the box depth (a camera outside a closed room would see only its outer wall), and
//   the vertical field of view fits the far face at `aspectRatio`, clamped to [45, 100] degrees.
// - Open scene: the camera stands outside, on the most open of the four horizontal sides (the
//   one where most of five rays from the centre, the axis and four 20-degree tilts, escape;
//   ties in the order +z, -z, +x, -x), so an
//   open-fronted box is seen through its opening. yFov 45 degrees, at the distance where the
//   bounding sphere fits both fields of view at `aspectRatio`.
// Returns aspectRatio 0 (taken from the image). An empty scene gets a camera at the origin.
Camera frameScene(const Scene& scene, double aspectRatio);

// The primary ray through image position (x, y) in pixels (0..width, 0..height, y down; pixel
// centres at +0.5) of a width x height image: a pinhole at camera.position, x to the right of
// `forward` (cross(forward, up)), y towards -up. Uses camera.aspectRatio when set (> 0), else
// width / height. Direction is unit.
Ray primaryRay(const Camera& camera, int width, int height, double x, double y);

// Ok when the camera's rays are ones the ray caster represents (finite, origin within 1e17 of the
// origin: scene/validate_scene.h's range), else an error naming the camera.
Expected<void> checkRayCamera(const Camera& camera);

}  // namespace daisy
