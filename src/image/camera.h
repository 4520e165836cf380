#pragma once
// Choosing the camera of a render (DESIGN.md section 7, issue 6): a glTF camera by name or index,
// else the scene's first camera, else an automatic framing; and primary rays through pixels.
#include <string>

#include "core/expected.h"
#include "radiosity/ray_caster.h"
#include "scene/scene.h"

namespace daisy {

// `selector` is a camera name, or a 0-based index among scene.cameras; empty = the first
// camera, or frameScene when the scene has none. Error (naming the scene file and listing the
// cameras it has) when the selector matches nothing.
Expected<Camera> chooseCamera(const Scene& scene, const std::string& selector);

// A camera that sees the whole scene: looks at the bounding box's centre from outside the box
// (along the axis the largest emitting-or-not faces look along, so a closed room is seen from
// inside its open side or from a point just inside the wall it faces), with a vertical field
// of view of 45 degrees, fitted so the bounding sphere fills the view at the given aspect.
Camera frameScene(const Scene& scene, double aspectRatio);

// The primary ray through image position (x, y) in pixels (0..width, 0..height, y down; pixel
// centres at +0.5) of a width x height image. Uses camera.aspectRatio when set (> 0), else
// width / height. Direction is unit.
Ray primaryRay(const Camera& camera, int width, int height, double x, double y);

}  // namespace daisy
