// The viewer's texture detail per vertex reproduces `daisy render`'s ratio texel / patch mean
// (image/texture_detail.h) wherever the rasteriser interpolates it: the oracle is the renderer's
// own SurfaceSampler at the same point, divided by the session's patch mean.
#if DAISY_HAVE_VIEWER
#include "viewer/detail_vertices.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "image/texture_detail.h"
#include "verify/scenes.h"

namespace daisy::viewer {
namespace {

// Two unit squares side by side: material 0 reflects through a 3 x 2 texture on TEXCOORD_1 with
// a KHR_texture_transform (bilinear, mirrored in u, repeated in v) times COLOR_0 (with
// `colours`); material 1 emits through the same image read nearest and clamped; material 2 has
// neither texture (COLOR_0 alone varies it).
Scene detailScene(bool colours) {
    Scene scene;
    verify::addQuad(scene.mesh, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, 0);
    verify::addQuad(scene.mesh, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, 1);
    verify::addQuad(scene.mesh, {2, 0, 0}, {3, 0, 0}, {3, 1, 0}, {2, 1, 0}, 2);
    const std::size_t vertices = scene.mesh.positions.size();
    for (std::size_t v = 0; v < vertices; ++v) {
        const Vec3d& p = scene.mesh.positions[v];
        scene.texCoords[0].push_back({float(p.x), float(p.y)});
        scene.texCoords[1].push_back({float(1.3 * p.x - 0.2), float(0.7 * p.y + 0.4)});
        if (colours)
            scene.vertexColors.push_back({float(0.4 + 0.2 * p.x), float(0.9 - 0.5 * p.y), 0.6f});
    }
    TextureImage image;
    image.width = 3;
    image.height = 2;
    image.rgb = {0.9f, 0.2f, 0.1f, 0.1f, 0.8f, 0.3f, 0.5f,  0.5f, 0.9f,
                 0.2f, 0.1f, 0.7f, 0.6f, 0.6f, 0.1f, 0.05f, 0.3f, 0.4f};
    scene.textures = {image};
    Material reflecting;
    reflecting.baseColor = {0.7, 0.5, 0.9};
    TextureRef bilinear;
    bilinear.image = 0;
    bilinear.texCoord = 1;
    bilinear.transform = textureTransform({0.1, -0.3}, 0.4, {1.5, 0.8});
    bilinear.wrapS = TextureWrap::MirroredRepeat;
    reflecting.baseColorTexture = bilinear;
    Material emitting;
    emitting.emissiveRgb = {4, 2, 1};
    TextureRef nearest;
    nearest.image = 0;
    nearest.nearest = true;
    nearest.wrapS = nearest.wrapT = TextureWrap::ClampToEdge;
    emitting.emissiveTexture = nearest;
    scene.materials = {reflecting, emitting, Material{}};
    return scene;
}

class DetailVerticesTest : public ::testing::TestWithParam<bool> {};

TEST_P(DetailVerticesTest, InterpolatedDetailIsTheRenderersRatio) {
    const bool colours = GetParam();
    const Scene scene = detailScene(colours);
    auto patches = buildPatchMesh(scene.mesh, 0.3);
    ASSERT_TRUE(patches) << patches.error().message;
    const PatchAppearance appearance = patchAppearance(scene, *patches);
    const DetailVertices detail = detailVertices(scene, *patches, appearance);
    const std::size_t n = patches->patchCount();
    ASSERT_EQ(detail.vertices.size(), n * 3 * kDetailFloats);
    // The white texel, and the image read two ways.
    ASSERT_EQ(detail.textures.size(), 3u);
    EXPECT_EQ(detail.textures[0].image, -1);
    const SurfaceSampler sampler(scene);
    int checked[3] = {0, 0, 0};
    uint32_t nextPatch = 0;
    for (const DetailRun& run : detail.runs) {
        ASSERT_EQ(run.firstPatch, nextPatch);  // the runs cover the patches in order
        nextPatch += run.patchCount;
        for (uint32_t i = run.firstPatch; i < run.firstPatch + run.patchCount; ++i) {
            const DetailSource follows = detailSource(appearance, i);
            const uint32_t material = patches->materials[i];
            ASSERT_EQ(follows,
                      material == 1                  ? DetailSource::Emission
                          : material == 0 || colours ? DetailSource::Reflectance
                                                     : DetailSource::None);
            const DetailTexture& texture = detail.textures[run.texture];
            if (follows != DetailSource::None) {
                EXPECT_EQ(texture.image, material == 2 ? -1 : 0);
            }
            // The shader samples the uv it is given: the transform is already applied.
            TextureRef shaderRef;
            shaderRef.image = 0;
            shaderRef.wrapS = texture.wrapS;
            shaderRef.wrapT = texture.wrapT;
            shaderRef.nearest = texture.nearest;
            const float* corners = detail.vertices.data() + std::size_t(i) * 3 * kDetailFloats;
            for (const auto& [a, b] :
                 {std::array<double, 2>{0.2, 0.3}, std::array<double, 2>{0.6, 0.1},
                  std::array<double, 2>{0.05, 0.9}}) {
                const double weight[3] = {1 - a - b, a, b};
                double at[kDetailFloats] = {};
                std::array<double, 3> source{0, 0, 0};
                for (int k = 0; k < 3; ++k) {
                    for (int f = 0; f < kDetailFloats; ++f)
                        at[f] += weight[k] * corners[k * kDetailFloats + f];
                    for (int j = 0; j < 3; ++j)
                        source[std::size_t(j)] +=
                            weight[k] * appearance.cornerWeights[i][std::size_t(k)][std::size_t(j)];
                }
                const uint32_t t = patches->sourceTriangle[i];
                const std::array<float, 3> texel = texture.image < 0
                    ? std::array<float, 3>{1, 1, 1}
                    : sampleTexture(scene.textures[0], shaderRef, at[0], at[1]);
                const Rgb3 point = follows == DetailSource::Emission
                    ? sampler.emission(t, source)
                    : sampler.reflectance(t, source);
                const Rgb3& mean = follows == DetailSource::Emission ? appearance.emission[i]
                                                                     : appearance.reflectance[i];
                for (int c = 0; c < 3; ++c) {
                    const double factor = at[2 + c];
                    if (follows == DetailSource::None) {
                        EXPECT_EQ(factor, -1) << i;  // ratio 1
                        continue;
                    }
                    const double expected = point[std::size_t(c)] / mean[std::size_t(c)];
                    EXPECT_NEAR(factor * texel[std::size_t(c)], expected, 1e-4 * expected + 1e-6)
                        << "patch " << i << " channel " << c;
                }
                ++checked[material];
            }
        }
    }
    EXPECT_EQ(nextPatch, n);
    for (int m = 0; m < 3; ++m)
        EXPECT_GT(checked[m], 0) << m;
}

INSTANTIATE_TEST_SUITE_P(WithAndWithoutVertexColours, DetailVerticesTest, ::testing::Bool());

TEST(DetailVerticesTestEmpty, NothingWhenNoColourVaries) {
    Scene scene;
    verify::addQuad(scene.mesh, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
    scene.materials = {Material{}};
    auto patches = buildPatchMesh(scene.mesh, 0);
    ASSERT_TRUE(patches);
    const PatchAppearance appearance = patchAppearance(scene, *patches);
    EXPECT_TRUE(detailVertices(scene, *patches, appearance).empty());
}

}  // namespace
}  // namespace daisy::viewer
#endif
