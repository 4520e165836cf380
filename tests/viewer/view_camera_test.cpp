// The viewer's camera matrix against the ray-cast renderer's primary rays (image/camera.h), the
// oracle `daisy render` is: a point on the ray through pixel (x, y) must project to (x, y).
#if DAISY_HAVE_VIEWER
#include "viewer/view_camera.h"

#include <gtest/gtest.h>

#include <cmath>

#include "image/camera.h"

namespace daisy::viewer {
namespace {

struct Projected {
    double x, y, depth;
};

Projected project(const std::array<float, 16>& m, const Vec3d& p, int width, int height) {
    double clip[4];
    for (int row = 0; row < 4; ++row) {
        clip[row] = m[std::size_t(row)] * p.x + m[std::size_t(4 + row)] * p.y +
            m[std::size_t(8 + row)] * p.z + m[std::size_t(12 + row)];
    }
    // Vulkan: NDC x, y in [-1, 1] (y down), framebuffer x = (ndc + 1) / 2 * width.
    return {(clip[0] / clip[3] + 1) / 2 * width, (clip[1] / clip[3] + 1) / 2 * height,
            clip[2] / clip[3]};
}

Camera tiltedCamera() {
    Camera camera;
    camera.position = Vec3d{0.3, 1.2, 2.5};
    camera.forward = normalize(Vec3d{-0.1, -0.3, -1});
    camera.up = normalize(cross(cross(camera.forward, Vec3d{0, 1, 0}), camera.forward));
    camera.yFovRad = 0.7;
    camera.zNear = 0.05;
    return camera;
}

// Frame all: every corner of the box projects inside the picture, at any aspect, and the box's
// bounding sphere touches the limiting edge (the distance is the smallest that fits it).
TEST(ViewCamera, FrameAllFitsTheWholeBoxTightly) {
    const Vec3d lo{-1, 0, -3}, hi{2, 1.5, 0.5};
    for (const double aspect : {0.5, 1.0, 16.0 / 9}) {
        const Framing framing = frameAll(tiltedCamera(), lo, hi, aspect);
        const Camera& camera = framing.camera;
        EXPECT_NEAR(
            length(camera.position + camera.forward * framing.orbitDistance - (lo + hi) * 0.5), 0,
            1e-12);
        const int height = 200, width = int(std::lround(200 * aspect));
        const auto m = viewProjection(camera, double(width) / height);
        for (int corner = 0; corner < 8; ++corner) {
            const Vec3d p{corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y,
                          corner & 4 ? hi.z : lo.z};
            const Projected q = project(m, p, width, height);
            EXPECT_GE(q.x, 0) << aspect;
            EXPECT_LE(q.x, width) << aspect;
            EXPECT_GE(q.y, 0) << aspect;
            EXPECT_LE(q.y, height) << aspect;
        }
        const double radius = 0.5 * length(hi - lo);
        const double halfY = 0.5 * camera.yFovRad;
        const double halfX = std::atan(std::tan(halfY) * aspect);
        EXPECT_NEAR(framing.orbitDistance * std::sin(std::min(halfX, halfY)), radius, 1e-9);
    }
}

TEST(ViewCamera, ProjectionInvertsThePrimaryRays) {
    const Camera camera = tiltedCamera();
    const int width = 320, height = 200;
    const auto m = viewProjection(camera, double(width) / height);
    for (const auto& [x, y] : {std::pair{0.5, 0.5}, {160.0, 100.0}, {319.5, 12.25}, {7.0, 199.0}}) {
        const Ray ray = primaryRay(camera, width, height, x, y);
        for (double t : {0.1, 1.0, 10.0}) {
            const Vec3d p =
                camera.position + Vec3d{ray.direction[0], ray.direction[1], ray.direction[2]} * t;
            const Projected q = project(m, p, width, height);
            EXPECT_NEAR(q.x, x, 1e-3) << t;
            EXPECT_NEAR(q.y, y, 1e-3) << t;
            // Reverse-Z: depth = zNear / view depth, in (0, 1] beyond the near plane.
            const double viewDepth = t *
                dot(normalize(camera.forward),
                    Vec3d{ray.direction[0], ray.direction[1], ray.direction[2]});
            EXPECT_NEAR(q.depth, camera.zNear / viewDepth, 1e-5) << t;
        }
    }
}

TEST(ViewCamera, OrbitKeepsTheTargetAndDistance) {
    ViewCamera view(tiltedCamera(), 2.0);
    const Vec3d target = view.target();
    view.orbit(0.7, -0.2);
    view.orbit(-2.0, 0.4);
    EXPECT_NEAR(length(view.camera().position - target), 2.0, 1e-9);
    EXPECT_NEAR(length(view.target() - target), 0.0, 1e-9);
    EXPECT_NEAR(dot(view.camera().forward, view.camera().up), 0.0, 1e-12);
    view.dolly(0.5);  // half the distance
    EXPECT_NEAR(view.orbitDistance(), 1.0, 1e-12);
    EXPECT_NEAR(length(view.target() - target), 0.0, 1e-9);
}

TEST(ViewCamera, PitchStopsShortOfTheVertical) {
    ViewCamera view(tiltedCamera(), 1.0);
    view.orbit(0, 10.0);  // far past straight up
    EXPECT_NEAR(std::asin(std::abs(view.camera().forward.y)), 89.0 * M_PI / 180.0, 1e-9);
}

TEST(ViewCamera, PickFindsTheNearestPatchOnTheRay) {
    // Two parallel unit squares (two patches each) at z = 0 and z = -1, seen from z = 2.
    PatchMesh mesh;
    for (double z : {0.0, -1.0}) {
        const uint32_t base = uint32_t(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(),
                              {Vec3d{-1, -1, z}, Vec3d{1, -1, z}, Vec3d{1, 1, z}, Vec3d{-1, 1, z}});
        mesh.patches.push_back({base, base + 1, base + 2});
        mesh.patches.push_back({base, base + 2, base + 3});
    }
    Camera camera;
    camera.position = Vec3d{0, 0, 2};
    camera.yFovRad = 1.0;
    // The pixel centre right of the middle sees the lower-right triangle (0) of the near square.
    EXPECT_EQ(pickPatch(mesh, camera, 100, 100, 60.5, 55.5), std::optional<uint32_t>(0));
    EXPECT_EQ(pickPatch(mesh, camera, 100, 100, 40.5, 45.5), std::optional<uint32_t>(1));
    EXPECT_EQ(pickPatch(mesh, camera, 100, 100, 0.5, 0.5), std::nullopt);  // past both squares
}

}  // namespace
}  // namespace daisy::viewer
#endif
