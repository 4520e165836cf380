#include "image/renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "image/camera.h"
#include "image/origin_camera.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

using test::originCamera;

// The quad z = -1, |x|, |y| <= 4, facing the camera: it fills a 60 degree view.
PatchMesh bigQuad() {
    TriangleMesh triangles;
    verify::addQuad(triangles, {-4, -4, -1}, {4, -4, -1}, {4, 4, -1}, {-4, 4, -1});
    return verify::patchesOf(triangles);
}

TEST(ImageRenderer, ConstantCornersRenderExactlyThatValue) {
    const PatchMesh mesh = bigQuad();
    const std::vector<float> value = {0.25f, 3.5f};
    std::vector<float> corners;
    for (std::size_t k = 0; k < mesh.patchCount() * 3; ++k)
        corners.insert(corners.end(), value.begin(), value.end());
    const std::vector<float> background = {-1, -1};
    for (int spp : {1, 4, 5}) {
        RenderSettings settings;
        settings.width = 33;
        settings.height = 17;
        settings.samplesPerPixel = spp;
        const auto image =
            renderCornerValues(mesh, originCamera(), settings, corners, 2, background);
        ASSERT_TRUE(image.ok()) << image.error().message;
        ASSERT_EQ(image->width, 33);
        ASSERT_EQ(image->height, 17);
        ASSERT_EQ(image->channels, 2);
        for (int y = 0; y < 17; ++y) {
            for (int x = 0; x < 33; ++x) {
                ASSERT_EQ(image->at(x, y)[0], 0.25f) << x << " " << y << " spp " << spp;
                ASSERT_EQ(image->at(x, y)[1], 3.5f) << x << " " << y << " spp " << spp;
            }
        }
    }
}

TEST(ImageRenderer, MissesTakeTheBackground) {
    const PatchMesh mesh = bigQuad();
    std::vector<float> corners(mesh.patchCount() * 3, 7.0f);
    Camera camera = originCamera();
    camera.forward = {0, 0, 1};  // looking away from the quad
    RenderSettings settings;
    settings.width = 8;
    settings.height = 6;
    const std::vector<float> background = {0.5f};
    const auto image = renderCornerValues(mesh, camera, settings, corners, 1, background);
    ASSERT_TRUE(image.ok());
    for (float v : image->pixels)
        EXPECT_EQ(v, 0.5f);
    // An empty mesh renders only background.
    const auto empty = renderCornerValues(PatchMesh{}, originCamera(), settings, {}, 1, background);
    ASSERT_TRUE(empty.ok()) << empty.error().message;
    for (float v : empty->pixels)
        EXPECT_EQ(v, 0.5f);
}

// Barycentric interpolation reproduces a function linear in position exactly on a planar
// triangle, so at pixel centres the image equals f(hit point) up to float rounding.
TEST(ImageRenderer, InterpolatesALinearRampExactly) {
    const PatchMesh mesh = bigQuad();
    const auto ramp = [](const Vec3d& p) { return 2.0 + 0.75 * p.x - 0.5 * p.y; };
    std::vector<float> corners;
    for (const auto& patch : mesh.patches) {
        for (uint32_t vertex : patch)
            corners.push_back(static_cast<float>(ramp(mesh.positions[vertex])));
    }
    const Camera camera = originCamera();
    RenderSettings settings;
    settings.width = 40;
    settings.height = 30;
    const std::vector<float> background = {-100};
    const auto image = renderCornerValues(mesh, camera, settings, corners, 1, background);
    ASSERT_TRUE(image.ok());
    double worst = 0;
    for (int y = 0; y < settings.height; ++y) {
        for (int x = 0; x < settings.width; ++x) {
            const Ray ray = primaryRay(camera, settings.width, settings.height, x + 0.5, y + 0.5);
            const double t = -1.0 / ray.direction[2];  // the plane z = -1
            const Vec3d hit(ray.direction[0] * t, ray.direction[1] * t, -1);
            worst = std::max(worst, std::abs(image->at(x, y)[0] - ramp(hit)));
        }
    }
    EXPECT_LT(worst, 2e-5);
    // The ramp really varies across the image (the oracle is not trivially constant).
    EXPECT_GT(image->at(39, 0)[0] - image->at(0, 0)[0], 1.0f);
    // Row 0 is the top of the image (+y), where -0.5 y makes the ramp lowest.
    EXPECT_LT(image->at(0, 0)[0] + 0.5f, image->at(0, 29)[0]);
}

TEST(ImageRenderer, DeterministicAcrossThreadCounts) {
    const PatchMesh mesh = bigQuad();
    std::vector<float> corners;
    for (std::size_t k = 0; k < mesh.patchCount() * 3; ++k)
        corners.push_back(float(k));
    const std::vector<float> background = {0};
    RenderSettings settings;
    settings.width = 31;
    settings.height = 23;
    settings.samplesPerPixel = 9;
    settings.threads = 1;
    const auto one = renderCornerValues(mesh, originCamera(), settings, corners, 1, background);
    settings.threads = 0;
    const auto all = renderCornerValues(mesh, originCamera(), settings, corners, 1, background);
    ASSERT_TRUE(one.ok() && all.ok());
    EXPECT_EQ(one->pixels, all->pixels);
}

TEST(ImageRenderer, RejectsAnEmptyImage) {
    RenderSettings settings;
    settings.width = 0;
    const std::vector<float> background = {0};
    EXPECT_FALSE(renderCornerValues(bigQuad(), originCamera(), settings,
                                    std::vector<float>(2 * 3, 0.0f), 1, background)
                     .ok());
}

}  // namespace
}  // namespace daisy

namespace daisy {
namespace {

// Supersampling positions (image/pixel_samples.h): a vertical or horizontal edge at image
// position e (pixels) covers a pixel by the fraction of its N x N samples on its side. The
// multi-jittered samples sit in N^2 distinct columns and rows at (k + 1/2) / N^2, so that is
// the analytic area fraction f rounded to a multiple of 1 / N^2: within 1 / (2 N^2), and exactly
// ceil(f N^2 - 1/2) / N^2 (stratum centres alone would round to 1 / N). Samples half a pixel
// off (a bug once seen) miss these by 1/2.
TEST(ImageRenderer, EdgeCoverageIsTheAreaFraction) {
    const Camera camera = originCamera();
    const int width = 8, height = 8;
    const double tanHalf = std::tan(0.5 * camera.yFovRad);
    for (const bool vertical : {true, false}) {
        for (const int spp : {1, 4, 16, 64}) {
            const int side = int(std::lround(std::sqrt(double(spp))));
            const int columns = side * side;
            for (const double at : {3.5, 3.25, 4.75, 4.8, 2.1}) {
                // The edge's line at depth 1 (z = -1), primaryRay's mapping (square image): the
                // quad covers image positions below `at` (left of it, or above it).
                TriangleMesh triangles;
                if (vertical) {
                    const double e = (2 * at / width - 1) * tanHalf;
                    verify::addQuad(triangles, {-10, -10, -1}, {e, -10, -1}, {e, 10, -1},
                                    {-10, 10, -1});
                } else {
                    const double e = (1 - 2 * at / height) * tanHalf;
                    verify::addQuad(triangles, {-10, e, -1}, {10, e, -1}, {10, 10, -1},
                                    {-10, 10, -1});
                }
                const PatchMesh mesh = verify::patchesOf(triangles);
                const std::vector<float> corners(mesh.patchCount() * 3, 1.0f);
                const float background = 0;
                RenderSettings settings;
                settings.width = width;
                settings.height = height;
                settings.samplesPerPixel = spp;
                const auto image =
                    renderCornerValues(mesh, camera, settings, corners, 1, {&background, 1});
                ASSERT_TRUE(image.ok()) << image.error().message;
                const int pixel = int(std::floor(at));
                const double fraction = at - pixel;
                // Sample columns (k + 0.5) / N^2 before the edge: k < f N^2 - 1/2.
                const double rounded = std::ceil(fraction * columns - 0.5) / columns;
                const double atSample = fraction * columns - 0.5;  // an edge through a sample
                for (int k = 0; k < width; ++k) {
                    const auto value = [&](int across) {
                        return vertical ? image->at(across, k)[0] : image->at(k, across)[0];
                    };
                    EXPECT_EQ(value(pixel - 1), 1.0f);
                    EXPECT_EQ(value(pixel + 1), 0.0f);
                    EXPECT_NEAR(value(pixel), fraction, 0.5 / columns + 1e-6)
                        << "spp " << spp << " edge " << at << " vertical " << vertical;
                    if (std::abs(atSample - std::round(atSample)) > 1e-3) {
                        EXPECT_NEAR(value(pixel), rounded, 1e-6)
                            << "spp " << spp << " edge " << at << " vertical " << vertical;
                    }
                }
            }
        }
    }
}

// patchesInView: a welded grid of 4 m cells at z = -1, facing the camera at the origin, whose
// view covers |x| < 0.78, |y| < 0.58 there: all of it lies in the one triangle with corners
// (-1, -3), (3, 1), (-1, 1), so that triangle is hit and the image needs it and the triangles
// sharing a corner with it (six around each corner of this grid: 13 in all). The same grid
// behind the camera is not needed.
TEST(ImageRenderer, PatchesInViewAreTheHitPatchesAndTheirVertexNeighbours) {
    TriangleMesh triangles;
    const auto addGrid = [&](double z) {
        const uint32_t base = uint32_t(triangles.positions.size());
        for (int j = 0; j <= 20; ++j) {
            for (int i = 0; i <= 20; ++i)
                triangles.positions.push_back({-41.0 + 4 * i, -43.0 + 4 * j, z});
        }
        const auto at = [&](int i, int j) { return base + uint32_t(j * 21 + i); };
        for (int j = 0; j < 20; ++j) {
            for (int i = 0; i < 20; ++i) {
                triangles.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                triangles.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            }
        }
    };
    addGrid(-1.0);
    addGrid(1.0);
    const PatchMesh mesh = verify::patchesOf(triangles);
    RenderSettings settings;
    settings.width = 24;
    settings.height = 18;
    settings.samplesPerPixel = 4;
    const auto needed = patchesInView(mesh, originCamera(), settings);
    ASSERT_TRUE(needed.ok()) << needed.error().message;
    ASSERT_EQ(needed->size(), mesh.patchCount());
    const std::vector<Vec3d> hit = {{-1, -3, -1}, {3, 1, -1}, {-1, 1, -1}};
    int count = 0;
    for (uint32_t p = 0; p < mesh.patchCount(); ++p) {
        bool touches = false;
        for (const uint32_t v : mesh.patches[p]) {
            for (const Vec3d& corner : hit)
                touches = touches || length(mesh.positions[v] - corner) == 0;
        }
        EXPECT_EQ((*needed)[p], touches ? 1 : 0) << "patch " << p;
        count += (*needed)[p];
    }
    EXPECT_EQ(count, 13);
}

}  // namespace
}  // namespace daisy
