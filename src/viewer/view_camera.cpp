#include "viewer/view_camera.h"

#include <algorithm>
#include <cmath>

#include "image/camera.h"
#include "shared/intersect.h"

namespace daisy::viewer {
namespace {

constexpr double kMaxPitch = 89.0 * 3.14159265358979323846 / 180.0;

// `v` rotated by `angle` (radians) about the unit `axis` (Rodrigues' formula).
Vec3d rotate(const Vec3d& v, const Vec3d& axis, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return v * c + cross(axis, v) * s + axis * (dot(axis, v) * (1 - c));
}

// `forward` turned by yaw about +y and pitch about its right axis, pitch limited.
Vec3d turned(const Vec3d& forward, double yawRad, double pitchRad) {
    const Vec3d up{0, 1, 0};
    const double pitch = std::asin(std::clamp(forward.y, -1.0, 1.0));
    const double limited = std::clamp(pitch + pitchRad, -kMaxPitch, kMaxPitch) - pitch;
    Vec3d f = rotate(forward, up, yawRad);
    Vec3d right = cross(f, up);
    if (length(right) < 1e-9) right = Vec3d{1, 0, 0};
    return normalize(rotate(f, normalize(right), limited));
}

}  // namespace

ViewCamera::ViewCamera(const Camera& camera, double orbitDistance)
    : camera_(camera), distance_(std::max(orbitDistance, 1e-6)) {
    camera_.forward = normalize(camera_.forward);
}

void ViewCamera::setForward(const Vec3d& forward) {
    camera_.forward = normalize(forward);
    Vec3d right = cross(camera_.forward, Vec3d{0, 1, 0});
    if (length(right) < 1e-9) right = Vec3d{1, 0, 0};
    camera_.up = normalize(cross(normalize(right), camera_.forward));
}

void ViewCamera::orbit(double yawRad, double pitchRad) {
    const Vec3d centre = target();
    setForward(turned(camera_.forward, yawRad, pitchRad));
    camera_.position = centre - camera_.forward * distance_;
}

void ViewCamera::look(double yawRad, double pitchRad) {
    setForward(turned(camera_.forward, yawRad, pitchRad));
}

void ViewCamera::pan(double right, double up) {
    const Vec3d r = normalize(cross(camera_.forward, camera_.up));
    camera_.position += r * right + camera_.up * up;
}

void ViewCamera::dolly(double factor) {
    const Vec3d centre = target();
    distance_ = std::max(distance_ * (1 - std::min(factor, 0.95)), 1e-6);
    camera_.position = centre - camera_.forward * distance_;
}

void ViewCamera::fly(double forward, double right, double up) {
    const Vec3d r = normalize(cross(camera_.forward, camera_.up));
    camera_.position += camera_.forward * forward + r * right + Vec3d{0, up, 0};
}

std::array<float, 16> viewProjection(const Camera& camera, double aspect) {
    const Vec3d f = normalize(camera.forward);
    const Vec3d r = normalize(cross(f, camera.up));
    const Vec3d u = cross(r, f);
    const Vec3d& e = camera.position;
    const double ty = 1.0 / std::tan(0.5 * camera.yFovRad);
    const double tx = ty / aspect;
    const double zNear = camera.zNear > 0 ? camera.zNear : 0.01;
    // Rows of clip = P * V: x = tx * dot(r, p - e), y = -ty * dot(u, p - e) (Vulkan's y is
    // down), z = zNear, w = dot(f, p - e).
    const double rows[4][4] = {
        {tx * r.x, tx * r.y, tx * r.z, -tx * dot(r, e)},
        {-ty * u.x, -ty * u.y, -ty * u.z, ty * dot(u, e)},
        {0, 0, 0, zNear},
        {f.x, f.y, f.z, -dot(f, e)},
    };
    std::array<float, 16> m{};
    for (int row = 0; row < 4; ++row) {
        for (int column = 0; column < 4; ++column)
            m[std::size_t(column * 4 + row)] = static_cast<float>(rows[row][column]);
    }
    return m;
}

double defaultOrbitDistance(const Camera& camera, const Vec3d& lo, const Vec3d& hi) {
    const Vec3d centre = (lo + hi) * 0.5;
    const double along = dot(centre - camera.position, normalize(camera.forward));
    return std::max(along, 0.01 * length(hi - lo) + 1e-6);
}

Framing frameAll(const Camera& camera, const Vec3d& lo, const Vec3d& hi, double aspect) {
    const Vec3d centre = (lo + hi) * 0.5;
    const double radius = std::max(0.5 * length(hi - lo), 1e-6);
    const double halfY = 0.5 * camera.yFovRad;
    const double halfX = std::atan(std::tan(halfY) * std::max(aspect, 1e-3));
    const double distance = radius / std::sin(std::min(halfX, halfY));
    Framing framing{camera, distance};
    framing.camera.forward = normalize(camera.forward);
    framing.camera.position = centre - framing.camera.forward * distance;
    return framing;
}

std::optional<uint32_t> pickPatch(const PatchMesh& mesh, const Camera& camera, int width,
                                  int height, double x, double y) {
    const Ray ray = primaryRay(camera, width, height, x, y);
    const shared::vec3 origin(ray.origin[0], ray.origin[1], ray.origin[2]);
    const shared::WatertightRay watertight = shared::makeWatertightRay(
        origin, shared::vec3(ray.direction[0], ray.direction[1], ray.direction[2]));
    const auto corner = [&](std::size_t p, int k) {
        const Vec3d& v = mesh.positions[mesh.patches[p][std::size_t(k)]];
        return shared::vec3(float(v.x), float(v.y), float(v.z));
    };
    std::optional<uint32_t> nearest;
    float best = INFINITY;
    for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
        float t = 0;
        if (shared::intersectTriangle(watertight, corner(p, 0), corner(p, 1), corner(p, 2), 0.0f,
                                      best, t)) {
            best = t;
            nearest = uint32_t(p);
        }
    }
    return nearest;
}

}  // namespace daisy::viewer
