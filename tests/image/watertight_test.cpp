// Primary rays through the edges that subdivision creates must hit one of the two
// patches sharing them. Oracle: inside a surface that covers the whole view, every sample hits,
// so the coverage (1 on every corner, 0 for a miss) is exactly 1 in every pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "geometry/patch_mesh.h"
#include "image/camera.h"
#include "image/renderer.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

// Pixels whose coverage is below 1: samples that missed every patch.
int holes(const PatchMesh& patches, const Camera& camera, int width, int height, int spp) {
    const std::vector<float> corners(patches.patchCount() * 3, 1.0f);
    const std::vector<float> background = {0.0f};
    RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.samplesPerPixel = spp;
    auto image = renderCornerValues(patches, camera, settings, corners, 1, background);
    EXPECT_TRUE(image) << image.error().message;
    if (!image) return -1;
    int count = 0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x)
            count += image->at(x, y)[0] < 1.0f - 1e-6f;
    }
    return count;
}

TEST(WatertightPrimaryRays, HeadOnSubdividedSquareHasNoHoles) {
    // The square |x|, |y| <= 1 at z = 0, subdivided to edges <= 0.05 (the automatic size's
    // scale for it), seen head-on from z = 1 with a view that stays inside it.
    TriangleMesh mesh;
    verify::addQuad(mesh, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
    auto patches = buildPatchMesh(mesh, 0.05);
    ASSERT_TRUE(patches) << patches.error().message;
    ASSERT_GT(patches->patchCount(), 1000u);
    Camera camera;
    camera.position = {0, 0, 1};
    camera.forward = {0, 0, -1};
    camera.up = {0, 1, 0};
    camera.yFovRad = 2 * std::atan(0.5);  // half-height 0.5, half-width 0.67 at 4:3
    for (const auto& [width, height] : {std::pair{320, 240}, {640, 480}, {1024, 768}}) {
        for (int spp : {1, 4}) {
            EXPECT_EQ(holes(*patches, camera, width, height, spp), 0)
                << width << " x " << height << ", " << spp << " spp";
        }
    }
}

TEST(WatertightPrimaryRays, ClosedSubdividedRoomHasNoHoles) {
    const TriangleMesh room = verify::closedRoom({0, 0, 0}, {4, 3, 5});
    auto patches = buildPatchMesh(room, 0.12);
    ASSERT_TRUE(patches) << patches.error().message;
    // From inside a closed room every ray hits a wall, whatever the direction.
    Camera camera;
    camera.position = {1.3, 1.1, 3.7};
    camera.yFovRad = 1.6;
    for (const Vec3d& forward : {Vec3d{0, 0, -1}, Vec3d{1, 0.2, 0.3}, Vec3d{-0.4, -0.7, 0.5}}) {
        camera.forward = normalize(forward);
        const Vec3d side = normalize(cross(camera.forward, Vec3d{0, 1, 0}));
        camera.up = normalize(cross(side, camera.forward));
        for (const auto& [width, height] : {std::pair{320, 240}, {640, 480}}) {
            EXPECT_EQ(holes(*patches, camera, width, height, 1), 0)
                << width << " x " << height << " looking along " << forward;
        }
    }
}

}  // namespace
}  // namespace daisy
