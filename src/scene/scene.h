#pragma once
// The one scene model every loader fills: world-space triangles in scene order with a material
// per triangle, the materials, and the cameras. Units are the file's (glTF: metres).
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
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
    int fileIndex = -1;  // its index in the file's camera list (glTF cameras[]); -1 = none
};

// A KHR_lights_punctual light in world space. Photometric as glTF states it: `intensity` is in
// candela (point, spot) or lux (directional), times `color` (linear sRGB). daisy uses the same
// scale as emissive surfaces (1 nit of glTF emissive radiance is exitance pi), so one candela at
// one metre gives an irradiance of 1 in those units (docs/scene_format.md).
struct PunctualLight {
    enum class Type { Point, Spot, Directional };
    std::string name;
    Type type = Type::Point;
    Vec3d position;  // point and spot
    Vec3d direction{0, 0, -1};  // unit: where the light shines (the node's -z)
    std::array<double, 3> color{1, 1, 1};
    double intensity = 1;
    double range = 0;  // metres; 0 = unlimited
    double innerConeRad = 0;  // spot
    double outerConeRad = 0.7853981633974483;  // spot, pi / 4 by default
    // The light's DAISY_materials_spectral emission, when given: its spectrum (times its scale
    // and `intensity`) replaces color's RGB spectrum.
    std::optional<SpectrumSpec> spectrum;
};

struct Scene {
    std::string path;  // the file it was loaded from
    TriangleMesh mesh;
    std::vector<Material> materials;
    std::vector<Camera> cameras;
    std::vector<PunctualLight> lights;
    // Cameras of the file that were skipped (glTF orthographic ones): "cameras[1] 'top'
    // (orthographic)", so `--camera 1` can say why it is not there.
    std::vector<std::pair<int, std::string>> skippedCameras;
    std::vector<TextureImage> textures;  // the images materials' TextureRefs name
    // Per vertex (index into mesh.positions): TEXCOORD_0 and TEXCOORD_1, and COLOR_0 (linear
    // RGB). Each is empty when no primitive has it, else sized like mesh.positions (vertices of
    // primitives without it get (0, 0) and white).
    std::array<std::vector<std::array<float, 2>>, 2> texCoords;
    std::vector<std::array<float, 3>> vertexColors;
    std::size_t degenerateDropped = 0;  // zero-area triangles removed on load
    std::vector<std::string> warnings;  // printed by the caller
};

}  // namespace daisy
