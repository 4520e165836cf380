// What real glTF files say about surfaces — textures (baseColorTexture,
// emissiveTexture, KHR_texture_transform, samplers), COLOR_0, doubleSided, emissive as radiance
// — and the warnings and refusals for what daisy does not model.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "core/strings.h"
#include "geometry/patch_mesh.h"
#include "image/image_io.h"
#include "scene/gltf_builder.h"
#include "scene/load_scene.h"
#include "scene/surface_appearance.h"
#include "spectral/color.h"
#include "test_util.h"

namespace daisy {
namespace {

using test::Float3;
using test::GltfBuilder;
using test::json;

const std::vector<Float3> kUnitSquare = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
const std::vector<std::array<float, 2>> kSquareUv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};

// The unit square as two triangles (0, 1, 2), (0, 2, 3) with uv = xy and `material`.
void addTexturedSquare(GltfBuilder& gltf, json material) {
    const int positions = gltf.addPositions(kUnitSquare);
    const int uv = gltf.addVec2(kSquareUv);
    const int indices = gltf.addIndices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3, 0});
    gltf.doc["accessors"][indices]["count"] = 6;
    gltf.doc["materials"] = json::array({std::move(material)});
    const int mesh = gltf.addMesh({{{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", uv}}},
                                    {"indices", indices},
                                    {"material", 0}}});
    gltf.setScene({gltf.addNode({{"mesh", mesh}})});
}

// A width x height PNG whose texel (x, y) is colour(x, y) (sRGB 8-bit), written beside the scene.
template <typename Colour>
void writeTexture(const std::filesystem::path& dir, const std::string& name, int width, int height,
                  Colour colour) {
    std::vector<uint8_t> bytes;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::array<uint8_t, 3> c = colour(x, y);
            for (uint8_t value : c)
                bytes.push_back(value);
        }
    }
    auto written = writePng((dir / name).string(), width, height, bytes);
    ASSERT_TRUE(written) << written.error().message;
}

Scene mustLoadScene(const std::string& path) {
    auto scene = loadScene(path, {});
    if (!scene) {
        ADD_FAILURE() << scene.error().message;
        return Scene{};
    }
    return std::move(*scene);
}

float linear(int srgb8) {
    return static_cast<float>(srgbDecode(srgb8 / 255.0));
}

TEST(GltfAppearance, TextureOnlyMaterialTakesTheTextureMeanNotAPerfectReflector) {
    // No baseColorFactor: glTF's default factor 1 times the texture (glTF 2.0 section 3.9.2).
    const auto dir = test::testTempDir();
    writeTexture(dir, "wall.png", 4, 4, [](int, int) {
        return std::array<uint8_t, 3>{188, 100, 40};
    });
    GltfBuilder gltf;
    gltf.doc["images"] = {{{"uri", "wall.png"}}};
    gltf.doc["textures"] = {{{"source", 0}}};
    addTexturedSquare(
        gltf,
        {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0}}}});
    const Scene scene = mustLoadScene(gltf.writeGltf(dir, "textured.gltf"));
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_TRUE(scene.materials[0].baseColorTexture.has_value());
    ASSERT_EQ(scene.warnings.size(), 1u);  // only that nothing emits: the texture was read
    EXPECT_NE(scene.warnings[0].find("no surface emits light"), std::string::npos);
    auto patches = buildPatchMesh(scene.mesh, 0.3);
    ASSERT_TRUE(patches);
    const PatchAppearance appearance = patchAppearance(scene, *patches);
    ASSERT_EQ(appearance.reflectance.size(), patches->patchCount());
    // A uniform texture: every patch's mean is the texel, sRGB-decoded (IEC 61966-2-1).
    for (std::size_t i = 0; i < patches->patchCount(); ++i) {
        EXPECT_TRUE(appearance.reflectanceVaries[i]);
        EXPECT_NEAR(appearance.reflectance[i][0], linear(188), 1e-6);
        EXPECT_NEAR(appearance.reflectance[i][1], linear(100), 1e-6);
        EXPECT_NEAR(appearance.reflectance[i][2], linear(40), 1e-6);
    }
}

TEST(GltfAppearance, PatchMeanIsTheAreaMeanOfTheTexture) {
    // Left half red, right half blue, NEAREST and clamped: triangle (0,0)(1,0)(1,1) (below the
    // diagonal) is 1/4 red by area, (0,0)(1,1)(0,1) is 3/4 red. Tolerance: the 16 x 16
    // sample grid straddles the colour edge by one sample row, under 1/16.
    const auto dir = test::testTempDir();
    writeTexture(dir, "halves.png", 16, 16, [](int x, int) {
        return x < 8 ? std::array<uint8_t, 3>{255, 0, 0} : std::array<uint8_t, 3>{0, 0, 255};
    });
    GltfBuilder gltf;
    gltf.doc["images"] = {{{"uri", "halves.png"}}};
    gltf.doc["samplers"] = {{{"magFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}}};
    gltf.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
    addTexturedSquare(gltf,
                      {{"pbrMetallicRoughness",
                        {{"baseColorFactor", {0.5, 1, 1, 1}},
                         {"baseColorTexture", {{"index", 0}}},
                         {"metallicFactor", 0}}}});
    const Scene scene = mustLoadScene(gltf.writeGltf(dir, "halves.gltf"));
    auto patches = buildPatchMesh(scene.mesh, 0);
    ASSERT_TRUE(patches);
    const PatchAppearance appearance = patchAppearance(scene, *patches);
    ASSERT_EQ(appearance.reflectance.size(), 2u);
    EXPECT_NEAR(appearance.reflectance[0][0], 0.5 * 0.25, 0.5 / 16);
    EXPECT_NEAR(appearance.reflectance[0][2], 0.75, 1.0 / 16);
    EXPECT_NEAR(appearance.reflectance[1][0], 0.5 * 0.75, 0.5 / 16);
    EXPECT_NEAR(appearance.reflectance[1][2], 0.25, 1.0 / 16);
    EXPECT_EQ(appearance.reflectance[0][1], 0.0f);
}

TEST(GltfAppearance, TextureTransformAndWrapModes) {
    // KHR_texture_transform: uv' = T R S uv. Scale 2 repeats a 2 x 1 texture twice across u.
    TextureImage image;
    image.width = 2;
    image.height = 1;
    image.rgb = {1, 0, 0, 0, 0, 1};  // red, blue
    TextureRef ref;
    ref.image = 0;
    ref.nearest = true;
    ref.transform = textureTransform({0, 0}, 0, {2, 1});
    EXPECT_EQ(sampleTexture(image, ref, 0.1, 0.5)[0], 1.0f);  // u' = 0.2: red
    EXPECT_EQ(sampleTexture(image, ref, 0.3, 0.5)[2], 1.0f);  // u' = 0.6: blue
    EXPECT_EQ(sampleTexture(image, ref, 0.6, 0.5)[0], 1.0f);  // u' = 1.2 wraps to 0.2: red
    ref.wrapS = TextureWrap::ClampToEdge;
    EXPECT_EQ(sampleTexture(image, ref, 0.6, 0.5)[2], 1.0f);  // clamped to the last texel
    ref.wrapS = TextureWrap::MirroredRepeat;
    EXPECT_EQ(sampleTexture(image, ref, 0.6, 0.5)[2], 1.0f);  // 1.2 mirrors to 0.8: blue
    // Offset and a quarter turn: (u, v) = (0.25, 0) -> R S uv = (0, -0.25), + offset (0.1, 1).
    const auto t = textureTransform({0.1, 1}, std::numbers::pi / 2, {1, 1});
    EXPECT_NEAR(t[0] * 0.25 + t[2], 0.1, 1e-12);
    EXPECT_NEAR(t[3] * 0.25 + t[5], 0.75, 1e-12);
    // Bilinear halfway between the two texel centres: the mean.
    ref.nearest = false;
    ref.transform = textureTransform({0, 0}, 0, {1, 1});
    ref.wrapS = TextureWrap::ClampToEdge;
    const auto mid = sampleTexture(image, ref, 0.5, 0.5);
    EXPECT_FLOAT_EQ(mid[0], 0.5f);
    EXPECT_FLOAT_EQ(mid[2], 0.5f);
}

TEST(GltfAppearance, VertexColoursMultiplyTheBaseColour) {
    // COLOR_0 (1,0,0), (0,1,0), (0,0,1) and factor 0.9: linear over the triangle, so its mean is
    // the centroid's, 0.9 / 3 per channel, for every patch's area-weighted total too.
    GltfBuilder gltf;
    const std::vector<Float3> triangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const std::vector<Float3> colours = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int positions = gltf.addPositions(triangle);
    const int colour = gltf.addPositions(colours);
    gltf.doc["materials"] = {{{"pbrMetallicRoughness",
                               {{"baseColorFactor", {0.9, 0.9, 0.9, 1}}, {"metallicFactor", 0}}}}};
    const int mesh = gltf.addMesh(
        {{{"attributes", {{"POSITION", positions}, {"COLOR_0", colour}}}, {"material", 0}}});
    gltf.setScene({gltf.addNode({{"mesh", mesh}})});
    const Scene scene = mustLoadScene(gltf.writeGltf(test::testTempDir(), "colours.gltf"));
    ASSERT_EQ(scene.vertexColors.size(), 3u);
    auto patches = buildPatchMesh(scene.mesh, 0.2);
    ASSERT_TRUE(patches);
    const PatchAppearance appearance = patchAppearance(scene, *patches);
    std::array<double, 3> total{0, 0, 0};
    double area = 0;
    for (std::size_t i = 0; i < patches->patchCount(); ++i) {
        for (int c = 0; c < 3; ++c)
            total[c] += appearance.reflectance[i][c] * patches->areas[i];
        area += patches->areas[i];
    }
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(total[c] / area, 0.3, 1e-6) << c;
}

TEST(GltfAppearance, EmissiveIsRadianceAndTheEmissiveTextureScalesIt) {
    // EmissiveStrengthTest-style: emissiveFactor 1 x strength 4 means radiance 4 (nits), so
    // the exitance is 4 pi; the emissive texture (uniform sRGB 128) scales it per patch.
    const auto dir = test::testTempDir();
    writeTexture(dir, "glow.png", 2, 2, [](int, int) {
        return std::array<uint8_t, 3>{128, 128, 128};
    });
    GltfBuilder gltf;
    gltf.doc["extensionsUsed"] = {"KHR_materials_emissive_strength"};
    gltf.doc["images"] = {{{"uri", "glow.png"}}};
    gltf.doc["textures"] = {{{"source", 0}}};
    addTexturedSquare(
        gltf,
        {{"emissiveFactor", {1, 1, 1}},
         {"emissiveTexture", {{"index", 0}}},
         {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}});
    const Scene scene = mustLoadScene(gltf.writeGltf(dir, "glow.gltf"));
    EXPECT_DOUBLE_EQ(scene.materials[0].emissiveRgb[1], 4 * std::numbers::pi);
    auto patches = buildPatchMesh(scene.mesh, 0);
    ASSERT_TRUE(patches);
    const PatchAppearance appearance = patchAppearance(scene, *patches);
    ASSERT_EQ(appearance.emission.size(), 2u);
    EXPECT_TRUE(appearance.emissionVaries[0]);
    EXPECT_NEAR(appearance.emission[0][0], 4 * std::numbers::pi * linear(128), 1e-5);
}

TEST(GltfAppearance, AnUnreadableTextureIsOneWarningAndNotAPerfectReflector) {
    GltfBuilder gltf;
    gltf.doc["images"] = {{{"uri", "missing.png"}}};
    gltf.doc["textures"] = {{{"source", 0}}};
    addTexturedSquare(
        gltf,
        {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0}}}});
    const std::string path = gltf.writeGltf(test::testTempDir(), "missing.gltf");
    const Scene scene = mustLoadScene(path);
    ASSERT_EQ(scene.warnings.size(), 2u);  // the image, and that nothing emits
    EXPECT_EQ(scene.warnings[0],
              path +
                  ": images[0] 'missing.png': the image file does not exist; the textures "
                  "using it are "
                  "dropped");
    EXPECT_FALSE(scene.materials[0].baseColorTexture.has_value());
    EXPECT_EQ(scene.materials[0].baseColor, (std::array<double, 3>{0.8, 0.8, 0.8}));
}

TEST(GltfAppearance, DoubleSidedMaterialsGetABackPatchPerFrontPatch) {
    GltfBuilder gltf;
    addTexturedSquare(gltf,
                      {{"doubleSided", true},
                       {"pbrMetallicRoughness",
                        {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}, {"metallicFactor", 0}}}});
    gltf.doc["materials"][0].erase("pbrMetallicRoughness");
    const Scene scene = mustLoadScene(gltf.writeGltf(test::testTempDir(), "two_sided.gltf"));
    ASSERT_TRUE(scene.materials[0].doubleSided);
    const std::vector<uint8_t> doubleSided = {1};
    auto patches = buildPatchMesh(scene.mesh, 0.25, UINT32_MAX, doubleSided);
    ASSERT_TRUE(patches);
    auto front = buildPatchMesh(scene.mesh, 0.25);
    ASSERT_TRUE(front);
    const std::size_t n = front->patchCount();
    ASSERT_EQ(patches->patchCount(), 2 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const uint32_t back = patches->backPatch[i];
        ASSERT_EQ(back, n + i);
        EXPECT_EQ(patches->backPatch[back], i);
        EXPECT_DOUBLE_EQ(patches->areas[back], patches->areas[i]);
        EXPECT_EQ(patches->normals[back], -patches->normals[i]);
        EXPECT_EQ(patches->sourceTriangle[back], patches->sourceTriangle[i]);
    }
}

TEST(GltfFeatures, UnknownRequiredExtensionIsRefusedNamingIt) {
    GltfBuilder gltf;
    gltf.addSingleTriangleScene({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    gltf.doc["extensionsUsed"] = {"EXT_unknown_geometry"};
    gltf.doc["extensionsRequired"] = {"EXT_unknown_geometry"};
    const std::string path = gltf.writeGltf(test::testTempDir(), "unknown.gltf");
    auto scene = loadScene(path, {});
    ASSERT_FALSE(scene);
    EXPECT_EQ(scene.error().message,
              path +
                  ": extensionsRequired: EXT_unknown_geometry is not supported: the file "
                  "cannot be read without it");
}

TEST(GltfFeatures, RequiredDracoWithNoCompressedPrimitiveLoads) {
    // KHR_draco_mesh_compression is decoded (gltf_draco.h; the compressed files are tested in
    // blender_corpus_test.cpp), so naming it without using it leaves the plain triangle.
    GltfBuilder gltf;
    gltf.addSingleTriangleScene({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    gltf.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    gltf.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    const Scene scene = mustLoadScene(gltf.writeGltf(test::testTempDir(), "draco.gltf"));
    ASSERT_EQ(scene.mesh.triangleCount(), 1u);
    EXPECT_EQ(scene.mesh.corner(0, 1), Vec3d(1, 0, 0));
}

TEST(GltfFeatures, OneWarningLinePerDroppedFeature) {
    GltfBuilder gltf;
    gltf.addSingleTriangleScene({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    gltf.doc["extensionsUsed"] = {"KHR_materials_transmission", "EXT_lights_image_based"};
    gltf.doc["materials"] = {{{"name", "chrome"}},  // metallicFactor defaults to 1
                             {{"name", "glass"},
                              {"alphaMode", "BLEND"},
                              {"pbrMetallicRoughness", {{"metallicFactor", 0}}},
                              {"extensions", {{"KHR_materials_transmission", json::object()}}}}};
    gltf.doc["meshes"][0]["primitives"][0]["material"] = 0;
    const std::string path = gltf.writeGltf(test::testTempDir(), "features.gltf");
    const Scene scene = mustLoadScene(path);
    const std::vector<std::string> expected = {
        path +
            ": metallic (material 'chrome') is not modelled: those surfaces are solved and "
            "rendered as diffuse",
        path +
            ": alpha blending (material 'glass') is not modelled: those surfaces are solved "
            "and rendered as diffuse",
        path +
            ": transmission (material 'glass') is not modelled: those surfaces are solved and "
            "rendered as diffuse",
        path + ": extensionsUsed: EXT_lights_image_based is not supported and is ignored"};
    ASSERT_GE(scene.warnings.size(), expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k)
        EXPECT_EQ(scene.warnings[k], expected[k]);
}

TEST(GltfFeatures, QuantizedPositionsAreDequantized) {
    // KHR_mesh_quantization: normalized SHORT positions (32767 = 1) scaled back by the node.
    GltfBuilder gltf;
    const std::vector<int16_t> values = {0, 0, 0, 32767, 0, 0, 0, -32767, 0, 0};
    const int view = gltf.addView(values.data(), 9 * sizeof(int16_t));
    const int accessor = gltf.addAccessor(view, 5122, 3, "VEC3");
    gltf.doc["accessors"][accessor]["normalized"] = true;
    gltf.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    gltf.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
    const int mesh = gltf.addMesh({{{"attributes", {{"POSITION", accessor}}}}});
    gltf.setScene({gltf.addNode({{"mesh", mesh}, {"scale", {2, 2, 2}}})});
    const Scene scene = mustLoadScene(gltf.writeGltf(test::testTempDir(), "quantized.gltf"));
    ASSERT_EQ(scene.mesh.triangleCount(), 1u);
    EXPECT_EQ(scene.mesh.positions[1], (Vec3d{2, 0, 0}));
    EXPECT_EQ(scene.mesh.positions[2], (Vec3d{0, -2, 0}));
}

TEST(GltfFeatures, PunctualLightsArePlacedByTheirNodes) {
    GltfBuilder gltf;
    gltf.addSingleTriangleScene({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    gltf.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    gltf.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "spot"},
         {"name", "uv spot"},
         {"intensity", 3},
         {"spot", {{"outerConeAngle", 0.5}}},
         {"extensions",
          {{"DAISY_materials_spectral",
            {{"emission", {{"preset", "blacklight"}, {"scale", 2}}}}}}}},
        {{"type", "directional"}, {"color", {1, 0.5, 0.25}}}};
    // The spot on a node turned a quarter about +x (its -z becomes -y: down), the sun unturned.
    const int spot = gltf.addNode({{"translation", {0, 2, 0}},
                                   {"rotation", {-std::sqrt(0.5), 0, 0, std::sqrt(0.5)}},
                                   {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    const int sun = gltf.addNode({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    gltf.doc["scenes"][0]["nodes"].push_back(spot);
    gltf.doc["scenes"][0]["nodes"].push_back(sun);
    const std::string path = gltf.writeGltf(test::testTempDir(), "lights.gltf");
    const Scene scene = mustLoadScene(path);
    ASSERT_EQ(scene.lights.size(), 2u);
    const PunctualLight& a = scene.lights[0];
    EXPECT_EQ(a.type, PunctualLight::Type::Spot);
    EXPECT_EQ(a.name, "uv spot");
    EXPECT_EQ(a.intensity, 3);
    EXPECT_EQ(a.outerConeRad, 0.5);
    EXPECT_EQ(a.innerConeRad, 0.0);
    EXPECT_NEAR(length(a.position - Vec3d{0, 2, 0}), 0, 1e-12);
    EXPECT_NEAR(length(a.direction - Vec3d{0, -1, 0}), 0, 1e-12);
    ASSERT_TRUE(a.spectrum.has_value());
    EXPECT_EQ(a.spectrum->scale, 2);
    const PunctualLight& b = scene.lights[1];
    EXPECT_EQ(b.type, PunctualLight::Type::Directional);
    EXPECT_EQ(b.color, (std::array<double, 3>{1, 0.5, 0.25}));
    EXPECT_EQ(b.direction, (Vec3d{0, 0, -1}));
    // Lights count as emitters: no "nothing emits" warning.
    for (const std::string& warning : scene.warnings)
        EXPECT_EQ(warning.find("no surface emits"), std::string::npos) << warning;

    gltf.doc["nodes"][spot]["extensions"]["KHR_lights_punctual"]["light"] = 7;
    const std::string bad = gltf.writeGltf(test::testTempDir(), "bad_light.gltf");
    auto refused = loadScene(bad, {});
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().message,
              bad +
                  ": nodes[1]: extensions.KHR_lights_punctual.light: light 7 is out of range "
                  "(the file has 2)");
}

// A point light needs only its node's position, which a zero scale keeps; a spot light on such
// a node has no direction and is refused with the place.
TEST(GltfFeatures, APointLightOnAZeroScaleNodeKeepsItsPosition) {
    GltfBuilder gltf;
    gltf.addSingleTriangleScene({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    gltf.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    gltf.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}}};
    const int node = gltf.addNode({{"translation", {0.25, 0.25, 1}},
                                   {"scale", {0, 0, 0}},
                                   {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    gltf.doc["scenes"][0]["nodes"].push_back(node);
    const Scene scene = mustLoadScene(gltf.writeGltf(test::testTempDir(), "point.gltf"));
    ASSERT_EQ(scene.lights.size(), 1u);
    EXPECT_EQ(scene.lights[0].position, (Vec3d{0.25, 0.25, 1}));

    gltf.doc["extensions"]["KHR_lights_punctual"]["lights"][0] = {
        {"type", "spot"}, {"spot", nlohmann::json::object()}};
    const std::string spot = gltf.writeGltf(test::testTempDir(), "spot.gltf");
    auto refused = loadScene(spot, {});
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find(
                  "extensions.KHR_lights_punctual.light: the node's transform is degenerate"),
              std::string::npos)
        << refused.error().message;
}

// libmeshoptimizer asserts (aborts) on a TRIANGLES count that is not a multiple of 3, a vertex
// stride that is not a multiple of 4 and a filter on the wrong stride or mode: each is refused
// with the view's place before any decoder runs.
TEST(GltfFeatures, MeshoptCountsStridesAndFiltersAreCheckedBeforeDecoding) {
    struct Case {
        nlohmann::json fields;
        std::string message;
    };
    const Case cases[] = {
        {{{"byteStride", 4}, {"count", 4}, {"mode", "TRIANGLES"}},
         ".count: 4 is not a multiple of 3, as TRIANGLES requires"},
        {{{"byteStride", 6}, {"count", 3}, {"mode", "ATTRIBUTES"}},
         ".byteStride: 6 is not a multiple of 4, as ATTRIBUTES requires"},
        {{{"byteStride", 12}, {"count", 3}, {"mode", "ATTRIBUTES"}, {"filter", "OCTAHEDRAL"}},
         ".filter: \"OCTAHEDRAL\" does not apply to mode \"ATTRIBUTES\" with byteStride 12"},
        {{{"byteStride", 4}, {"count", 3}, {"mode", "TRIANGLES"}, {"filter", "EXPONENTIAL"}},
         ".filter: \"EXPONENTIAL\" does not apply to mode \"TRIANGLES\" with byteStride 4"},
    };
    int k = 0;
    for (const Case& c : cases) {
        GltfBuilder gltf;
        gltf.addSingleTriangleScene({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
        const std::string data(40, '\x7f');
        const int view = gltf.addView(data.data(), data.size());
        nlohmann::json ext = {{"buffer", 0},
                              {"byteOffset", gltf.doc["bufferViews"][view]["byteOffset"]},
                              {"byteLength", 40}};
        ext.update(c.fields);
        gltf.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"] = ext;
        gltf.doc["extensionsUsed"] = {"EXT_meshopt_compression"};
        gltf.doc["extensionsRequired"] = {"EXT_meshopt_compression"};
        const std::string path =
            gltf.writeGltf(test::testTempDir(), concat("meshopt", k++, ".gltf"));
        auto scene = loadScene(path, {});
        ASSERT_FALSE(scene);
        EXPECT_EQ(scene.error().message,
                  path + ": bufferViews[0].extensions.EXT_meshopt_compression" + c.message);
    }
}

TEST(GltfFeatures, UndecodableMeshoptDataIsRefusedNamingTheView) {
    GltfBuilder gltf;
    gltf.addSingleTriangleScene({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    const std::string garbage(40, '\x7f');
    const int view = gltf.addView(garbage.data(), garbage.size());
    gltf.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"] = {
        {"buffer", 0},      {"byteOffset", gltf.doc["bufferViews"][view]["byteOffset"]},
        {"byteLength", 40}, {"byteStride", 12},
        {"count", 3},       {"mode", "ATTRIBUTES"}};
    gltf.doc["extensionsUsed"] = {"EXT_meshopt_compression"};
    gltf.doc["extensionsRequired"] = {"EXT_meshopt_compression"};
    const std::string path = gltf.writeGltf(test::testTempDir(), "garbage.gltf");
    auto scene = loadScene(path, {});
    ASSERT_FALSE(scene);
    EXPECT_EQ(scene.error().message,
              path +
                  ": bufferViews[0].extensions.EXT_meshopt_compression: the compressed data "
                  "cannot be decoded");
}

}  // namespace
}  // namespace daisy
