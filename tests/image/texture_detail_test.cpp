// The image's texture detail is the texel against the patch mean, so the pixels of a
// patch average to what the solve gave it (energy-consistent), and the two faces of a
// double-sided surface show their own radiosity.
#include "image/texture_detail.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "image/camera.h"
#include "spectral/color.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

// The square |x|, |y| <= 1 at z = 0 facing +z, uv = ((x + 1) / 2, (1 - y) / 2), textured with a
// 2 x 1 image, left half red and right half blue (nearest, clamped).
Scene texturedSquare() {
    Scene scene;
    verify::addQuad(scene.mesh, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
    scene.texCoords[0] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    TextureImage image;
    image.width = 2;
    image.height = 1;
    image.rgb = {0.9f, 0.1f, 0.1f, 0.1f, 0.1f, 0.9f};
    scene.textures = {image};
    Material material;
    material.baseColor = {1, 1, 1};
    TextureRef ref;
    ref.image = 0;
    ref.nearest = true;
    ref.wrapS = ref.wrapT = TextureWrap::ClampToEdge;
    material.baseColorTexture = ref;
    scene.materials = {material};
    return scene;
}

Camera headOn() {
    Camera camera;
    camera.position = {0, 0, 2};
    camera.forward = {0, 0, -1};
    camera.up = {0, 1, 0};
    camera.yFovRad = 2 * std::atan(0.5);  // sees |x|, |y| <= 1 exactly at 1:1
    return camera;
}

TEST(TextureDetail, PixelsAverageToThePatchRadianceAndShowTheTexels) {
    const Scene scene = texturedSquare();
    auto patches = buildPatchMesh(scene.mesh, 0);
    ASSERT_TRUE(patches);
    const PatchAppearance appearance = patchAppearance(scene, *patches);
    // Every corner carries the XYZ of linear sRGB (0.5, 0.5, 0.5) and coverage 1.
    const Xyz grey = linearSrgbToXyz(Rgb{0.5, 0.5, 0.5});
    std::vector<float> corners;
    for (std::size_t k = 0; k < patches->patchCount() * 3; ++k) {
        for (double v : grey)
            corners.push_back(static_cast<float>(v));
        corners.push_back(1.0f);
    }
    const SurfaceDetail detail(scene, *patches, appearance, 0);
    ASSERT_FALSE(detail.empty());
    RenderSettings settings;
    settings.width = settings.height = 64;
    settings.samplesPerPixel = 4;
    const std::vector<float> background(4, 0.0f);
    auto image = renderCornerValues(*patches, headOn(), settings, corners, 4, background, &detail);
    ASSERT_TRUE(image) << image.error().message;
    std::array<double, 3> mean{0, 0, 0}, left{0, 0, 0}, right{0, 0, 0};
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            const float* p = image->at(x, y);
            const Rgb rgb = xyzToLinearSrgb(Xyz{p[0], p[1], p[2]});
            for (int c = 0; c < 3; ++c) {
                mean[c] += rgb[c] / (64.0 * 64);
                (x < 32 ? left : right)[c] += rgb[c] / (32.0 * 64);
            }
        }
    }
    // The image's mean is the solved radiance (each patch's texels average to its mean; the
    // nearest-texel edge on the diagonal-split patches leaves ~1/64 of pixel rounding).
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(mean[c], 0.5, 0.02) << c;
    // Texel detail: red on the left, blue on the right.
    EXPECT_GT(left[0], 3 * left[2]);
    EXPECT_GT(right[2], 3 * right[0]);
}

TEST(TextureDetail, ADoubleSidedSurfaceShowsTheFaceTheRaySees) {
    TriangleMesh mesh;
    verify::addQuad(mesh, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});  // faces +z
    const std::vector<uint8_t> doubleSided = {1};
    auto patches = buildPatchMesh(mesh, 0, UINT32_MAX, doubleSided);
    ASSERT_TRUE(patches);
    ASSERT_EQ(patches->patchCount(), 4u);
    // Front patches carry 1, back patches 2.
    std::vector<float> corners;
    for (std::size_t i = 0; i < 4; ++i) {
        for (int k = 0; k < 3; ++k)
            corners.push_back(i < 2 ? 1.0f : 2.0f);
    }
    Scene scene;
    scene.mesh = mesh;
    scene.materials = {Material{}};
    const PatchAppearance none;
    const SurfaceDetail detail(scene, *patches, none, 0);
    ASSERT_FALSE(detail.empty());
    RenderSettings settings;
    settings.width = settings.height = 16;
    const std::vector<float> background = {0.0f};
    Camera front = headOn();
    Camera back = front;
    back.position = {0, 0, -2};
    back.forward = {0, 0, 1};
    for (const auto& [camera, expected] : {std::pair{front, 1.0f}, std::pair{back, 2.0f}}) {
        auto image =
            renderCornerValues(*patches, camera, settings, corners, 1, background, &detail);
        ASSERT_TRUE(image);
        for (int y = 0; y < 16; ++y) {
            for (int x = 0; x < 16; ++x)
                EXPECT_FLOAT_EQ(image->at(x, y)[0], expected) << x << ", " << y;
        }
    }
}

}  // namespace
}  // namespace daisy
