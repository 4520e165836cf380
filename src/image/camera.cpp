#include "image/camera.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <vector>

#include "core/strings.h"

namespace daisy {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kOpenSceneYFovRad = 45 * kPi / 180;
constexpr double kMinRoomYFovRad = 45 * kPi / 180;
constexpr double kMaxRoomYFovRad = 100 * kPi / 180;
constexpr double kRoomWallMargin = 0.02;  // fraction of the box depth

// Distance along the ray to triangle (a, b, c) (Moller & Trumbore 1997), or infinity. Edges
// and corners count as hits, with a little slack, so a ray aimed exactly at a room's corner
// does not slip out between its triangles.
double rayTriangle(const Vec3d& origin, const Vec3d& direction, const Vec3d& a, const Vec3d& b,
                   const Vec3d& c) {
    const Vec3d e1 = b - a;
    const Vec3d e2 = c - a;
    const Vec3d p = cross(direction, e2);
    const double det = dot(e1, p);
    constexpr double kNone = std::numeric_limits<double>::infinity();
    if (std::abs(det) < 1e-300) return kNone;
    const Vec3d s = origin - a;
    const double u = dot(s, p) / det;
    constexpr double kSlack = 1e-9;
    if (u < -kSlack || u > 1 + kSlack) return kNone;
    const Vec3d q = cross(s, e1);
    const double v = dot(direction, q) / det;
    if (v < -kSlack || u + v > 1 + kSlack) return kNone;
    const double t = dot(e2, q) / det;
    return t > 0 ? t : kNone;
}

// The farthest hit of the ray along `direction` from `origin` over all triangles: its distance
// (negative when the ray escapes) and the hit triangle's (unnormalised) normal.
double farthestHit(const TriangleMesh& mesh, const Vec3d& origin, const Vec3d& direction,
                   Vec3d& normal) {
    double farthest = -1;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const Vec3d a = mesh.corner(t, 0);
        const Vec3d b = mesh.corner(t, 1);
        const Vec3d c = mesh.corner(t, 2);
        const double hit = rayTriangle(origin, direction, a, b, c);
        if (std::isfinite(hit) && hit > farthest) {
            farthest = hit;
            normal = areaVector2(a, b, c);
        }
    }
    return farthest;
}

// The closed-room test of frameScene: from the centre, every one of the 26 directions hits a
// triangle, and most of the farthest hits face back towards the centre.
bool looksLikeClosedRoom(const TriangleMesh& mesh, const Vec3d& centre) {
    int facingCentre = 0;
    int directions = 0;
    for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
            for (int dz = -1; dz <= 1; ++dz) {
                if (dx == 0 && dy == 0 && dz == 0) continue;
                ++directions;
                const Vec3d direction = normalize(Vec3d(dx, dy, dz));
                Vec3d normal;
                if (farthestHit(mesh, centre, direction, normal) < 0) return false;  // escapes
                if (dot(normal, direction) < 0) ++facingCentre;
            }
        }
    }
    return 2 * facingCentre > directions;
}

// How many of five rays from the centre towards horizontal unit direction `side` (the axis, and
// tilted 20 degrees up, down, left and right) escape the scene: how open that side is.
int escapingRays(const TriangleMesh& mesh, const Vec3d& centre, const Vec3d& side) {
    const Vec3d up{0, 1, 0};
    const Vec3d across = cross(side, up);
    const double tilt = std::tan(20 * kPi / 180);
    int escaping = 0;
    for (const Vec3d& offset : {Vec3d(), up * tilt, up * -tilt, across * tilt, across * -tilt}) {
        Vec3d normal;
        if (farthestHit(mesh, centre, normalize(side + offset), normal) < 0) ++escaping;
    }
    return escaping;
}

std::string cameraList(const Scene& scene) {
    if (scene.cameras.empty()) return "the scene has no cameras";
    std::string list = "the scene's cameras are";
    for (std::size_t i = 0; i < scene.cameras.size(); ++i) {
        const Camera& camera = scene.cameras[i];
        list += concat(i == 0 ? " " : ", ",
                       camera.fileIndex >= 0 ? static_cast<long long>(camera.fileIndex)
                                             : static_cast<long long>(i),
                       " \"", camera.name, "\"");
    }
    return list;
}

}  // namespace

Expected<Camera> chooseCamera(const Scene& scene, const std::string& selector, double aspectRatio) {
    if (selector.empty()) {
        if (!scene.cameras.empty()) return scene.cameras.front();
        return frameScene(scene, aspectRatio);
    }
    for (const Camera& camera : scene.cameras) {
        if (camera.name == selector) return camera;
    }
    std::size_t index = 0;
    const char* end = selector.data() + selector.size();
    const auto [rest, status] = std::from_chars(selector.data(), end, index);
    if (status == std::errc() && rest == end) {
        // A number is the camera's index in the file (glTF cameras[]), whatever the order the
        // node tree reaches the cameras in; cameras without one (made in memory) count in order.
        const bool fileIndexed = std::any_of(scene.cameras.begin(), scene.cameras.end(),
                                             [](const Camera& c) { return c.fileIndex >= 0; });
        for (const Camera& camera : scene.cameras) {
            if (fileIndexed && camera.fileIndex == static_cast<long long>(index)) return camera;
        }
        if (!fileIndexed && index < scene.cameras.size()) return scene.cameras[index];
        for (const auto& [skippedIndex, description] : scene.skippedCameras) {
            if (skippedIndex == static_cast<long long>(index)) {
                return Error{concat(scene.path, ": camera ", selector, " is ", description,
                                    ", which daisy skips (", cameraList(scene), ")")};
            }
        }
    }
    return Error{concat(scene.path, ": no camera named or numbered \"", selector, "\" (",
                        cameraList(scene), ")")};
}

Camera frameScene(const Scene& scene, double aspectRatio) {
    Camera camera;
    camera.name = "automatic";
    camera.aspectRatio = 0;
    camera.up = {0, 1, 0};
    const double aspect = aspectRatio > 0 ? aspectRatio : 1.0;
    const Bounds3d bounds = meshBounds(scene.mesh);
    if (bounds.empty()) {
        camera.yFovRad = kOpenSceneYFovRad;
        return camera;
    }
    const Vec3d centre = bounds.center();
    const Vec3d extent = bounds.extent();
    // View axis: z (glTF's default view direction) when the box is at least as wide in x as
    // deep in z, else x. `back` points from the centre towards the camera side, `width` is the
    // box's extent across the view.
    // An open scene (a model) is seen from the front, +z: glTF models face +z (glTF 2.0
    // section 3.4), so a model deeper than wide is not shown from its side.
    const bool closed = looksLikeClosedRoom(scene.mesh, centre);
    const bool alongZ = !closed || extent.x >= extent.z;
    Vec3d back = alongZ ? Vec3d(0, 0, 1) : Vec3d(1, 0, 0);
    if (!closed) {
        // Stand on the most open horizontal side, so an open-fronted box (the Cornell box) is
        // seen through its opening; ties keep the order preferred axis +, -, other axis +, -.
        const Vec3d other = alongZ ? Vec3d(1, 0, 0) : Vec3d(0, 0, 1);
        int best = -1;
        for (const Vec3d& side : {back, -back, other, -other}) {
            const int escaping = escapingRays(scene.mesh, centre, side);
            if (escaping > best) best = escaping, back = side;
        }
    }
    const bool viewAlongZ = back.z != 0;
    const double depth = viewAlongZ ? extent.z : extent.x;
    const double width = viewAlongZ ? extent.x : extent.z;
    camera.forward = -back;
    const double radius = std::max(0.5 * bounds.diagonal(), 1e-9);
    if (closed) {
        const double distance = depth * (1 - kRoomWallMargin);
        camera.position = centre + back * (depth * (0.5 - kRoomWallMargin));
        const double halfHeight = std::max(0.5 * extent.y, 0.5 * width / aspect);
        const double fov = distance > 0 ? 2 * std::atan(halfHeight / distance) : kMaxRoomYFovRad;
        camera.yFovRad = std::clamp(fov, kMinRoomYFovRad, kMaxRoomYFovRad);
        camera.zNear = 1e-4 * radius;
        return camera;
    }
    camera.yFovRad = kOpenSceneYFovRad;
    const double tanHalfY = std::tan(0.5 * camera.yFovRad);
    const double halfFit = std::atan(std::min(tanHalfY, tanHalfY * aspect));
    camera.position = centre + back * (radius / std::sin(halfFit));
    camera.zNear = 1e-3 * radius;
    return camera;
}

Ray primaryRay(const Camera& camera, int width, int height, double x, double y) {
    const double aspect = camera.aspectRatio > 0 ? camera.aspectRatio : double(width) / height;
    const double tanHalf = std::tan(0.5 * camera.yFovRad);
    const Vec3d forward = normalize(camera.forward);
    const Vec3d right = normalize(cross(forward, camera.up));
    const Vec3d up = cross(right, forward);
    const double sx = (2 * x / width - 1) * aspect * tanHalf;
    const double sy = (1 - 2 * y / height) * tanHalf;
    const Vec3d direction = normalize(forward + right * sx + up * sy);
    Ray ray;
    for (int axis = 0; axis < 3; ++axis) {
        ray.origin[axis] = static_cast<float>(camera.position[axis]);
        ray.direction[axis] = static_cast<float>(direction[axis]);
    }
    return ray;
}

Expected<void> checkRayCamera(const Camera& camera) {
    // Well inside the ray caster's largest distance (1.844e18), and what scene/validate_scene.h
    // allows for scenes.
    constexpr double kMaxRayOrigin = 1e17;
    // The ray caster asserts on rays it cannot represent (|origin| under 1.8e18, finite
    // direction); scenes are range-checked on load, but a camera may come from elsewhere.
    if (!isFinite(camera.position) || !isFinite(camera.forward) || !isFinite(camera.up) ||
        std::max({std::abs(camera.position.x), std::abs(camera.position.y),
                  std::abs(camera.position.z)}) > kMaxRayOrigin) {
        return Error{concat("camera '", camera.name, "' at ", camera.position,
                            " is outside what float32 ray tracing represents (coordinates up to ",
                            formatNumber(kMaxRayOrigin), ")")};
    }
    return {};
}

}  // namespace daisy
