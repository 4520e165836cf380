#include "scene/gltf_loader.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <variant>
#include <vector>

#include "scene/gltf_builder.h"
#include "scene/material_extension.h"
#include "test_util.h"

namespace daisy {
namespace {

using nlohmann::json;
using test::Float3;
using test::GltfBuilder;

constexpr double kTolerance = 1e-12;

const std::vector<Float3> kUnitTriangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
const std::vector<Float3> kUnitSquare = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};

Scene mustLoad(const std::string& path) {
    auto scene = loadGltf(path);
    if (!scene) {
        ADD_FAILURE() << scene.error().message;
        return Scene{};
    }
    return std::move(*scene);
}

// The error message of a load that must fail; checks that it starts with the path.
std::string loadError(const std::string& path) {
    auto scene = loadGltf(path);
    if (scene) {
        ADD_FAILURE() << path << " loaded without an error";
        return "";
    }
    const std::string& message = scene.error().message;
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    return message;
}

void expectNear(const Vec3d& actual, const Vec3d& expected, double tolerance = kTolerance) {
    EXPECT_NEAR(actual.x, expected.x, tolerance) << actual << " vs " << expected;
    EXPECT_NEAR(actual.y, expected.y, tolerance) << actual << " vs " << expected;
    EXPECT_NEAR(actual.z, expected.z, tolerance) << actual << " vs " << expected;
}

Vec3d corner(const Scene& scene, std::size_t triangle, int k) {
    return scene.mesh.corner(triangle, k);
}

Vec3d toVec(const Float3& p) {
    return {p[0], p[1], p[2]};
}

Vec3d faceNormal(const Scene& scene, std::size_t triangle) {
    return normalize(areaVector2(corner(scene, triangle, 0), corner(scene, triangle, 1),
                                 corner(scene, triangle, 2)));
}

TEST(GltfLoader, FlattensNodeHierarchyWithTrsAndMatrix) {
    // Oracle: glTF 2.0 section 3.5.3, world = parent (T * R * S) * child matrix. R is 90 degrees
    // about +Z, mapping (x, y, z) to (-y, x, z).
    GltfBuilder gltf;
    const int lifted = gltf.addPositions({{0, 0, 1}, {1, 0, 1}, {0, 1, 1}});
    const int flat = gltf.addPositions(kUnitTriangle);
    const int parentMesh = gltf.addMesh({{{"attributes", {{"POSITION", lifted}}}}});
    const int childMesh = gltf.addMesh({{{"attributes", {{"POSITION", flat}}}}});
    const double s = std::sqrt(0.5);
    gltf.addNode({{"translation", {1, 2, 3}},
                  {"rotation", {0, 0, s, s}},
                  {"scale", {2, 3, 4}},
                  {"mesh", parentMesh},
                  {"children", {1}}});
    gltf.addNode(
        {{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1}}, {"mesh", childMesh}});
    gltf.addNode({{"translation", {0, 0, -5}}, {"mesh", childMesh}});
    gltf.setScene({0, 2});
    const auto path = gltf.writeGltf(test::testTempDir(), "hierarchy.gltf");

    const Scene scene = mustLoad(path);
    EXPECT_EQ(scene.path, path);
    ASSERT_EQ(scene.mesh.triangleCount(), 3u);
    ASSERT_EQ(scene.mesh.positions.size(), 9u);
    const std::vector<Vec3d> expected = {
        {1, 2, 7},  {1, 4, 7},  {-2, 2, 7},  // parent: S, R, T
        {1, 22, 3}, {1, 24, 3}, {-2, 22, 3},  // child: +10 x, then the parent's transform
        {0, 0, -5}, {1, 0, -5}, {0, 1, -5}};  // second root, after the first root's subtree
    for (std::size_t i = 0; i < expected.size(); ++i)
        expectNear(scene.mesh.positions[i], expected[i]);
    for (uint32_t t = 0; t < 3; ++t) {
        EXPECT_EQ(scene.mesh.triangles[t], (std::array<uint32_t, 3>{3 * t, 3 * t + 1, 3 * t + 2}));
    }
}

TEST(GltfLoader, WithoutScenesEveryRootNodeIsLoaded) {
    // A file without scenes is valid glTF; the loader then takes every root node, in index order.
    GltfBuilder gltf;
    const int accessor = gltf.addPositions(kUnitTriangle);
    const int mesh = gltf.addMesh({{{"attributes", {{"POSITION", accessor}}}}});
    gltf.addNode({{"mesh", mesh}, {"children", {2}}});
    gltf.addNode({{"mesh", mesh}, {"translation", {0, 0, 1}}});
    gltf.addNode({{"mesh", mesh}, {"translation", {0, 0, 2}}});
    const Scene scene = mustLoad(gltf.writeGltf(test::testTempDir(), "no_scene.gltf"));
    ASSERT_EQ(scene.mesh.triangleCount(), 3u);
    EXPECT_EQ(corner(scene, 1, 0).z, 2);  // node 0's child before the second root
    EXPECT_EQ(corner(scene, 2, 0).z, 1);
}

TEST(GltfLoader, IndexedWithEveryIndexTypeAndNonIndexedTriangles) {
    GltfBuilder gltf;
    const int square = gltf.addPositions(kUnitSquare);
    const int six =
        gltf.addPositions({{0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {0, 0, 2}, {1, 0, 2}, {0, 1, 2}});
    const int bytes = gltf.addIndices(std::vector<uint8_t>{0, 1, 2, 0, 2, 3});
    const int shorts = gltf.addIndices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
    const int ints = gltf.addIndices(std::vector<uint32_t>{0, 1, 2, 0, 2, 3});
    json primitives = json::array();
    for (int indices : {bytes, shorts, ints}) {
        primitives.push_back({{"attributes", {{"POSITION", square}}}, {"indices", indices}});
    }
    primitives.push_back({{"attributes", {{"POSITION", six}}}});
    const int mesh = gltf.addMesh(primitives);
    gltf.setScene({gltf.addNode({{"mesh", mesh}})});
    const Scene scene = mustLoad(gltf.writeGltf(test::testTempDir(), "indexed.gltf"));

    ASSERT_EQ(scene.mesh.triangleCount(), 8u);
    ASSERT_EQ(scene.mesh.positions.size(), 18u);  // one position per accessor element per primitive
    for (uint32_t p = 0; p < 3; ++p) {
        EXPECT_EQ(scene.mesh.triangles[2 * p],
                  (std::array<uint32_t, 3>{4 * p, 4 * p + 1, 4 * p + 2}));
        EXPECT_EQ(scene.mesh.triangles[2 * p + 1],
                  (std::array<uint32_t, 3>{4 * p, 4 * p + 2, 4 * p + 3}));
        expectNear(corner(scene, 2 * p + 1, 2), toVec(kUnitSquare[3]));
    }
    EXPECT_EQ(scene.mesh.triangles[6], (std::array<uint32_t, 3>{12, 13, 14}));
    EXPECT_EQ(scene.mesh.triangles[7], (std::array<uint32_t, 3>{15, 16, 17}));
    expectNear(corner(scene, 7, 0), {0, 0, 2});
}

TEST(GltfLoader, TriangleStripAndFanFollowTheSpecOrder) {
    // Oracle: glTF 2.0 section 3.7.2.1. Strip triangle i = {v_i, v_(i+1+i%2), v_(i+2-i%2)};
    // fan triangle i = {v_(i+1), v_(i+2), v_0}.
    const std::vector<Float3> strip = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    const std::vector<Float3> fan = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {-1, 1, 1}};
    GltfBuilder gltf;
    const int stripAccessor = gltf.addPositions(strip);
    const int fanAccessor = gltf.addPositions(fan);
    const int reversed = gltf.addIndices(std::vector<uint16_t>{4, 3, 2, 1, 0});
    const int mesh = gltf.addMesh(
        {{{"attributes", {{"POSITION", stripAccessor}}}, {"mode", 5}},
         {{"attributes", {{"POSITION", fanAccessor}}}, {"mode", 6}},
         {{"attributes", {{"POSITION", fanAccessor}}}, {"mode", 6}, {"indices", reversed}}});
    gltf.setScene({gltf.addNode({{"mesh", mesh}})});
    const Scene scene = mustLoad(gltf.writeGltf(test::testTempDir(), "strip_fan.gltf"));

    ASSERT_EQ(scene.mesh.triangleCount(), 2u + 3u + 3u);
    const std::vector<std::array<Float3, 3>> expected = {
        {strip[0], strip[1], strip[2]}, {strip[1], strip[3], strip[2]}, {fan[1], fan[2], fan[0]},
        {fan[2], fan[3], fan[0]},       {fan[3], fan[4], fan[0]},       {fan[3], fan[2], fan[4]},
        {fan[2], fan[1], fan[4]},       {fan[1], fan[0], fan[4]}};
    for (std::size_t t = 0; t < expected.size(); ++t) {
        for (int k = 0; k < 3; ++k)
            expectNear(corner(scene, t, k), toVec(expected[t][k]));
    }
    // The strip's alternation keeps both of its triangles facing +Z.
    expectNear(faceNormal(scene, 0), {0, 0, 1});
    expectNear(faceNormal(scene, 1), {0, 0, 1});
}

TEST(GltfLoader, MirroringNodeReversesWindingToKeepTheNormalSide) {
    // Oracle: a normal transforms by the inverse transpose of the linear part (glTF 2.0 section
    // 3.7.4); for a diagonal matrix diag(a, b, c) that maps +Z to sign(c) * +Z. The unit
    // triangle's normal is +Z.
    GltfBuilder gltf;
    const int accessor = gltf.addPositions(kUnitTriangle);
    const int mesh = gltf.addMesh({{{"attributes", {{"POSITION", accessor}}}}});
    gltf.addNode({{"mesh", mesh}});
    gltf.addNode({{"mesh", mesh}, {"scale", {-1, 1, 1}}});
    gltf.addNode({{"mesh", mesh}, {"scale", {-1, -1, -1}}});
    gltf.addNode({{"mesh", mesh}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1}}});
    gltf.setScene({0, 1, 2, 3});
    const Scene scene = mustLoad(gltf.writeGltf(test::testTempDir(), "mirror.gltf"));

    ASSERT_EQ(scene.mesh.triangleCount(), 4u);
    expectNear(faceNormal(scene, 0), {0, 0, 1});
    expectNear(faceNormal(scene, 1), {0, 0, 1});
    expectNear(faceNormal(scene, 2), {0, 0, -1});
    expectNear(faceNormal(scene, 3), {0, 0, -1});  // same positions as node 0, reversed winding
    EXPECT_EQ(scene.mesh.triangles[1], (std::array<uint32_t, 3>{3, 5, 4}));
}

TEST(GltfLoader, GlbAndSideBinLoadTheSameSceneAsEmbeddedGltf) {
    GltfBuilder gltf;
    const int square = gltf.addPositions(kUnitSquare);
    const int indices = gltf.addIndices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
    const int mesh = gltf.addMesh(
        {{{"attributes", {{"POSITION", square}}}, {"indices", indices}, {"material", 0}},
         {{"attributes", {{"POSITION", square}}}, {"mode", 6}}});
    gltf.doc["materials"] = {
        {{"name", "red"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.1, 0.1, 1}}}}}};
    gltf.setScene({gltf.addNode({{"mesh", mesh}, {"translation", {0.5, 0, 0}}})});
    const auto dir = test::testTempDir();
    const Scene embedded = mustLoad(gltf.writeGltf(dir, "scene.gltf"));
    const Scene sideBin = mustLoad(gltf.writeGltfWithBin(dir, "side.gltf", "side.bin"));
    const Scene binary = mustLoad(test::writeFile(dir, "scene.glb", gltf.glbBytes()));

    ASSERT_EQ(embedded.mesh.triangleCount(), 4u);
    for (const Scene* other : {&sideBin, &binary}) {
        EXPECT_EQ(other->mesh.positions, embedded.mesh.positions);
        EXPECT_EQ(other->mesh.triangles, embedded.mesh.triangles);
        EXPECT_EQ(other->mesh.materials, embedded.mesh.materials);
        ASSERT_EQ(other->materials.size(), 2u);
        EXPECT_EQ(other->materials[0].baseColor, embedded.materials[0].baseColor);
    }
    EXPECT_EQ(binary.mesh.materials, (std::vector<uint32_t>{0, 0, 1, 1}));
    expectNear(binary.mesh.positions[2], {1.5, 1, 0});
}

TEST(GltfLoader, MaterialsFromBaseColorEmissiveAndStrength) {
    GltfBuilder gltf;
    const int accessor = gltf.addPositions(kUnitTriangle);
    json primitives = json::array();
    for (int material : {0, 1, 2}) {
        primitives.push_back({{"attributes", {{"POSITION", accessor}}}, {"material", material}});
    }
    primitives.push_back({{"attributes", {{"POSITION", accessor}}}});
    const int mesh = gltf.addMesh(primitives);
    gltf.setScene({gltf.addNode({{"mesh", mesh}})});
    gltf.doc["extensionsUsed"] = {"KHR_materials_emissive_strength"};
    gltf.doc["materials"] = {
        {{"name", "wall"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.4, 0.6, 0.5}}}}},
        {{"emissiveFactor", {1, 0.5, 0.25}},
         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}},
        {{"emissiveFactor", {0.1, 0.2, 0.3}}}};
    const auto path = gltf.writeGltf(test::testTempDir(), "materials.gltf");
    const Scene scene = mustLoad(path);

    ASSERT_EQ(scene.materials.size(), 4u);
    EXPECT_EQ(scene.mesh.materials, (std::vector<uint32_t>{0, 1, 2, 3}));
    EXPECT_EQ(scene.materials[0].name, "wall");
    EXPECT_EQ(scene.materials[0].baseColor,
              (std::array<double, 3>{0.2, 0.4, 0.6}));  // alpha ignored
    EXPECT_EQ(scene.materials[0].emissiveRgb, (std::array<double, 3>{0, 0, 0}));
    EXPECT_FALSE(scene.materials[0].isEmissive());
    EXPECT_EQ(scene.materials[1].name, "material1");
    EXPECT_EQ(scene.materials[1].origin, path + ": materials[1]");
    EXPECT_EQ(scene.materials[1].baseColor, (std::array<double, 3>{1, 1, 1}));  // glTF default
    // glTF's emissive is radiance: exitance = pi x factor x strength.
    constexpr double kPi = std::numbers::pi;
    EXPECT_EQ(scene.materials[1].emissiveRgb,
              (std::array<double, 3>{kPi * 1 * 4, kPi * 0.5 * 4, kPi * 0.25 * 4}));
    EXPECT_EQ(scene.materials[2].emissiveRgb,
              (std::array<double, 3>{kPi * 0.1, kPi * 0.2, kPi * 0.3}));  // strength 1
    EXPECT_EQ(scene.materials[3].name, "default");
    EXPECT_EQ(scene.materials[3].baseColor, (std::array<double, 3>{0.8, 0.8, 0.8}));
    EXPECT_FALSE(scene.materials[3].isEmissive());
}

TEST(GltfLoader, NoDefaultMaterialWhenEveryPrimitiveHasOne) {
    GltfBuilder gltf;
    gltf.addSingleTriangleScene(kUnitTriangle);
    gltf.doc["meshes"][0]["primitives"][0]["material"] = 0;
    gltf.doc["materials"] = {{{"name", "only"}}};
    const Scene scene = mustLoad(gltf.writeGltf(test::testTempDir(), "one.gltf"));
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].name, "only");
    EXPECT_EQ(scene.mesh.materials, (std::vector<uint32_t>{0}));
}

TEST(GltfLoader, SpectralExtensionArrivesInTheMaterial) {
    GltfBuilder gltf;
    gltf.addSingleTriangleScene(kUnitTriangle);
    gltf.doc["meshes"][0]["primitives"][0]["material"] = 0;
    gltf.doc["extensionsUsed"] = {kSpectralExtensionName};
    gltf.doc["materials"] = {{{"name", "lamp"},
                              {"extensions",
                               {{kSpectralExtensionName,
                                 {{"reflectance", {{"rgb", {0.1, 0.2, 0.3}}}},
                                  {"emission", {{"preset", "blacklight"}, {"scale", 20}}}}}}}}};
    const Scene scene = mustLoad(gltf.writeGltf(test::testTempDir(), "spectral.gltf"));

    ASSERT_EQ(scene.materials.size(), 1u);
    const MaterialExtension& spectral = scene.materials[0].spectral;
    ASSERT_TRUE(spectral.reflectance.has_value());
    const auto* rgb = std::get_if<RgbSpectrum>(&spectral.reflectance->shape);
    ASSERT_NE(rgb, nullptr);
    EXPECT_EQ(rgb->rgb, (std::array<double, 3>{0.1, 0.2, 0.3}));
    ASSERT_TRUE(spectral.emission.has_value());
    const auto* preset = std::get_if<PresetSpectrum>(&spectral.emission->shape);
    ASSERT_NE(preset, nullptr);
    EXPECT_EQ(preset->name, "blacklight");
    EXPECT_EQ(spectral.emission->scale, 20);
    EXPECT_FALSE(spectral.fluorescence.has_value());
    EXPECT_TRUE(scene.materials[0].isEmissive());
}

TEST(GltfLoader, SparseAccessorSubstitutesElements) {
    // Oracle: glTF 2.0 section 3.6.2.3; element 1 of the base data is replaced by (5, 6, 7).
    GltfBuilder gltf;
    gltf.addSingleTriangleScene(kUnitTriangle);
    const std::vector<uint8_t> targets = {1};
    const std::vector<Float3> values = {{5, 6, 7}};
    const int targetView = gltf.addView(targets.data(), targets.size());
    const int valueView = gltf.addView(values.data(), sizeof(Float3));
    gltf.doc["accessors"][0]["sparse"] = {
        {"count", 1},
        {"indices", {{"bufferView", targetView}, {"componentType", 5121}}},
        {"values", {{"bufferView", valueView}}}};
    const Scene scene = mustLoad(gltf.writeGltf(test::testTempDir(), "sparse.gltf"));
    ASSERT_EQ(scene.mesh.positions.size(), 3u);
    expectNear(scene.mesh.positions[0], {0, 0, 0});
    expectNear(scene.mesh.positions[1], {5, 6, 7});
    expectNear(scene.mesh.positions[2], {0, 1, 0});
}

TEST(GltfLoader, CommittedLampRoomFixture) {
    // tests/data/gltf/lamp_room.gltf: a room scaled by 2 whose floor (the unit square turned -90
    // degrees about X) faces +Y and whose lamp (turned +90 degrees about X, raised by 1, drawn as
    // a fan) faces -Y; Rx(-90) maps (x, y, 0) to (x, 0, -y).
    const Scene scene = mustLoad(test::testDataPath("gltf/lamp_room.gltf"));
    ASSERT_EQ(scene.mesh.triangleCount(), 4u);
    EXPECT_EQ(scene.mesh.materials, (std::vector<uint32_t>{0, 0, 1, 1}));
    expectNear(corner(scene, 0, 2), {2, 0, -2});
    expectNear(corner(scene, 2, 0), {2, 2, 0});  // fan triangle 0 starts at v1
    for (std::size_t t = 0; t < 4; ++t)
        expectNear(faceNormal(scene, t), {0, t < 2 ? 1.0 : -1.0, 0});
    ASSERT_EQ(scene.materials.size(), 2u);
    EXPECT_EQ(scene.materials[0].baseColor, (std::array<double, 3>{0.5, 0.5, 0.5}));
    EXPECT_TRUE(scene.materials[0].spectral.reflectance.has_value());
    EXPECT_EQ(scene.materials[1].name, "uv_lamp");
    constexpr double kPi = std::numbers::pi;  // exitance = pi x radiance
    EXPECT_EQ(scene.materials[1].emissiveRgb, (std::array<double, 3>{kPi * 5, kPi * 2.5, kPi * 5}));
    ASSERT_TRUE(scene.materials[1].spectral.emission.has_value());
    EXPECT_EQ(scene.materials[1].spectral.emission->scale, 20);
    ASSERT_EQ(scene.cameras.size(), 1u);
    EXPECT_EQ(scene.cameras[0].name, "eye");  // unnamed camera: the node's name
    expectNear(scene.cameras[0].position, {1, 1, 6});
    expectNear(scene.cameras[0].forward, {0, 0, -1});
}

TEST(GltfLoader, PerspectiveCamerasInWorldSpace) {
    // Oracle: the camera looks down its local -Z with +Y up (glTF 2.0 section 3.10.1). A
    // 90-degree turn about +Y maps -Z to -X; the parent scales by 2 and moves by (0, 0, 1).
    GltfBuilder gltf;
    const double s = std::sqrt(0.5);
    gltf.addNode({{"translation", {0, 0, 1}}, {"scale", {2, 2, 2}}, {"children", {1, 2, 3}}});
    gltf.addNode(
        {{"name", "eye"}, {"camera", 0}, {"translation", {0, 1, 5}}, {"rotation", {0, s, 0, s}}});
    gltf.addNode({{"name", "Side"}, {"camera", 1}});
    gltf.addNode({{"camera", 2}});
    gltf.addNode({{"camera", 1}});
    gltf.doc["cameras"] = {
        {{"name", "main"},
         {"type", "perspective"},
         {"perspective", {{"yfov", 0.7}, {"aspectRatio", 1.5}, {"znear", 0.1}, {"zfar", 100}}}},
        {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.05}}}},
        {{"type", "orthographic"},
         {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}}};
    gltf.setScene({0, 4});
    const Scene scene = mustLoad(gltf.writeGltf(test::testTempDir(), "cameras.gltf"));

    ASSERT_EQ(scene.cameras.size(), 3u);
    const Camera& main = scene.cameras[0];
    EXPECT_EQ(main.name, "main");
    expectNear(main.position, {0, 2, 11});
    expectNear(main.forward, {-1, 0, 0});
    expectNear(main.up, {0, 1, 0});
    EXPECT_EQ(main.yFovRad, 0.7);
    EXPECT_EQ(main.aspectRatio, 1.5);
    EXPECT_EQ(main.zNear, 0.1);
    EXPECT_EQ(main.zFar, 100);
    EXPECT_EQ(scene.cameras[1].name, "Side");  // unnamed camera: the node's name
    expectNear(scene.cameras[1].position, {0, 0, 1});
    expectNear(scene.cameras[1].forward, {0, 0, -1});
    EXPECT_EQ(scene.cameras[1].aspectRatio, 0);
    EXPECT_EQ(scene.cameras[1].zFar, 0);
    EXPECT_EQ(scene.cameras[2].name, "camera2");  // neither named: its place in Scene::cameras
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("nodes[3]: cameras[2] is orthographic"), std::string::npos)
        << scene.warnings[0];
    EXPECT_TRUE(scene.mesh.triangles.empty());
}

TEST(GltfLoader, PointsAndLinesAreSkippedWithAWarningNamingTheMesh) {
    GltfBuilder gltf;
    gltf.addSingleTriangleScene(kUnitTriangle);
    const auto dir = test::testTempDir();
    gltf.doc["meshes"][0]["name"] = "wire";
    gltf.doc["meshes"][0]["primitives"][1] = {{"attributes", {{"POSITION", 0}}}, {"mode", 1}};
    gltf.doc["meshes"][0]["primitives"][2] = {{"attributes", {{"POSITION", 0}}}, {"mode", 0}};
    const std::string path = gltf.writeGltf(dir, "scene.gltf");
    auto scene = loadGltf(path);
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_EQ(scene->mesh.triangleCount(), 1u);  // the TRIANGLES primitive only
    ASSERT_EQ(scene->warnings.size(), 1u);
    EXPECT_EQ(scene->warnings[0],
              path +
                  ": meshes[0] 'wire': LINES, POINTS primitives skipped (only "
                  "triangles become patches)");
}

// One malformed variant of a valid one-triangle scene per case, and the place it must name.
struct BrokenCase {
    const char* name;
    std::function<void(GltfBuilder&)> breakIt;
    const char* expected;
};

void PrintTo(const BrokenCase& brokenCase, std::ostream* out) {
    *out << brokenCase.name;
}

class GltfBrokenFile : public ::testing::TestWithParam<BrokenCase> {};

TEST_P(GltfBrokenFile, ErrorNamesTheFileAndThePlace) {
    GltfBuilder gltf;
    gltf.addSingleTriangleScene(kUnitTriangle);
    GetParam().breakIt(gltf);
    const std::string message = loadError(gltf.writeGltf(test::testTempDir(), "broken.gltf"));
    EXPECT_NE(message.find(GetParam().expected), std::string::npos) << message;
}

void setPositions(GltfBuilder& gltf, const std::vector<Float3>& positions) {
    std::memcpy(gltf.bin.data(), positions.data(), positions.size() * sizeof(Float3));
}

void useIndices(GltfBuilder& gltf, const std::vector<uint16_t>& indices) {
    gltf.doc["meshes"][0]["primitives"][0]["indices"] = gltf.addIndices(indices);
}

const float kNan = std::numeric_limits<float>::quiet_NaN();

INSTANTIATE_TEST_SUITE_P(
    GltfLoaderErrors, GltfBrokenFile,
    ::testing::Values(
        BrokenCase{"IndexValueOutOfRange",
                   [](GltfBuilder& g) {
                       useIndices(g, {0, 1, 2, 0, 2, 57});
                   },
                   "broken.gltf: meshes[0].primitives[0]: index 57 at position 5 is out of range "
                   "(accessor 0 has 3 vertices)"},
        BrokenCase{"AccessorExceedsItsBufferView",
                   [](GltfBuilder& g) { g.doc["accessors"][0]["count"] = 4; },
                   "meshes[0].primitives[0]: attributes.POSITION: accessors[0]: 4 elements of 12 "
                   "bytes, 12 apart from byte 0, exceed bufferViews[0] (36 bytes)"},
        BrokenCase{"AccessorOffsetPastItsBufferView",
                   [](GltfBuilder& g) { g.doc["accessors"][0]["byteOffset"] = 4; },
                   "accessors[0]: 3 elements of 12 bytes"},
        BrokenCase{"BufferViewExceedsItsBuffer",
                   [](GltfBuilder& g) { g.doc["bufferViews"][0]["byteOffset"] = 8; },
                   "bufferViews[0]: bytes [8, 44) exceed buffers[0] (36 bytes)"},
        BrokenCase{"MeshIndex", [](GltfBuilder& g) { g.doc["nodes"][0]["mesh"] = 5; },
                   "nodes[0].mesh: mesh 5 is out of range (the file has 1)"},
        BrokenCase{"MaterialIndex",
                   [](GltfBuilder& g) { g.doc["meshes"][0]["primitives"][0]["material"] = 3; },
                   "meshes[0].primitives[0]: material 3 is out of range (the file has 0)"},
        BrokenCase{"PositionAccessorIndex",
                   [](GltfBuilder& g) {
                       g.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9;
                   },
                   "meshes[0].primitives[0]: attributes.POSITION: accessor 9 is out of range"},
        BrokenCase{"IndicesAccessorIndex",
                   [](GltfBuilder& g) { g.doc["meshes"][0]["primitives"][0]["indices"] = 9; },
                   "indices accessor out of bounds"},  // caught by tinygltf itself
        BrokenCase{"BufferViewIndex",
                   [](GltfBuilder& g) { g.doc["accessors"][0]["bufferView"] = 5; },
                   "accessors[0]: bufferView 5 is out of range"},
        BrokenCase{"BufferIndex", [](GltfBuilder& g) { g.doc["bufferViews"][0]["buffer"] = 3; },
                   "bufferViews[0]: buffer 3 is out of range"},
        BrokenCase{"SceneNodeIndex", [](GltfBuilder& g) { g.doc["scenes"][0]["nodes"] = {7}; },
                   "scenes[0].nodes[0]: node 7 is out of range (the file has 1)"},
        BrokenCase{"ChildIndex", [](GltfBuilder& g) { g.doc["nodes"][0]["children"] = {4}; },
                   "nodes[0].children[0]: node 4 is out of range"},
        BrokenCase{"CameraIndex", [](GltfBuilder& g) { g.doc["nodes"][0]["camera"] = 2; },
                   "nodes[0].camera: camera 2 is out of range (the file has 0)"},
        BrokenCase{"DefaultSceneIndex", [](GltfBuilder& g) { g.doc["scene"] = 4; },
                   "scene: scene 4 is out of range"},
        BrokenCase{"NodeCycle",
                   [](GltfBuilder& g) {
                       g.doc["nodes"][0]["children"] = {1};
                       g.addNode({{"children", {0}}});
                   },
                   "nodes[0] is reached a second time, from nodes[1].children[0]: the node "
                   "hierarchy has a cycle"},
        BrokenCase{"NonFinitePosition",
                   [](GltfBuilder& g) {
                       setPositions(g, {{0, 0, 0}, {1, kNan, 0}, {0, 1, 0}});
                   },
                   "meshes[0].primitives[0]: attributes.POSITION: accessors[0]: element 1 is not "
                   "finite"},
        BrokenCase{"PositionNotVec3",
                   [](GltfBuilder& g) { g.doc["accessors"][0]["type"] = "VEC2"; },
                   "accessors[0]: VEC2 FLOAT where VEC3 FLOAT (or KHR_mesh_quantization's BYTE or "
                   "SHORT) is "
                   "required"},
        BrokenCase{"IndicesNotUnsigned",
                   [](GltfBuilder& g) {
                       useIndices(g, {0, 1, 2});
                       g.doc["accessors"][1]["componentType"] = 5122;
                   },
                   "meshes[0].primitives[0]: indices: accessors[1]: SCALAR SHORT where"},
        BrokenCase{"NoPosition",
                   [](GltfBuilder& g) {
                       g.doc["meshes"][0]["primitives"][0]["attributes"] = {{"NORMAL", 0}};
                   },
                   "meshes[0].primitives[0]: has no POSITION attribute"},
        BrokenCase{"IncompleteTriangleList",
                   [](GltfBuilder& g) {
                       useIndices(g, {0, 1, 2, 0});
                   },
                   "meshes[0].primitives[0]: 4 vertices do not make whole triangles"},
        BrokenCase{"SparseIndexOutOfRange",
                   [](GltfBuilder& g) {
                       const std::vector<uint16_t> targets = {3, 0};
                       const int view = g.addView(targets.data(), 4);
                       g.doc["accessors"][0]["sparse"] = {
                           {"count", 1},
                           {"indices", {{"bufferView", view}, {"componentType", 5123}}},
                           {"values", {{"bufferView", 0}}}};
                   },
                   "accessors[0].sparse.indices[0]: element 3 is out of range"},
        BrokenCase{"RotationLength",
                   [](GltfBuilder& g) {
                       g.doc["nodes"][0]["rotation"] = {0, 0, 1};
                   },
                   "nodes[0].rotation: has 3 numbers, expected 4"},
        BrokenCase{"ZeroQuaternion",
                   [](GltfBuilder& g) {
                       g.doc["nodes"][0]["rotation"] = {0, 0, 0, 0};
                   },
                   "nodes[0].rotation: not a unit quaternion"},
        BrokenCase{"BaseColorOver1",
                   [](GltfBuilder& g) {
                       g.doc["materials"] = {
                           {{"pbrMetallicRoughness", {{"baseColorFactor", {1.5, 0, 0, 1}}}}}};
                   },
                   "broken.gltf: materials[0].pbrMetallicRoughness.baseColorFactor[0]: 1.5 is "
                   "outside [0, 1]"},
        BrokenCase{"BaseColorNegative",
                   [](GltfBuilder& g) {
                       g.doc["materials"] = {
                           {{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, -0.1, 1}}}}}};
                   },
                   "materials[0].pbrMetallicRoughness.baseColorFactor[2]: -0.1 is outside [0, 1]"},
        BrokenCase{"NegativeEmissiveStrength",
                   [](GltfBuilder& g) {
                       g.doc["materials"] = {
                           {{"emissiveFactor", {1, 1, 1}},
                            {"extensions",
                             {{"KHR_materials_emissive_strength", {{"emissiveStrength", -2}}}}}}};
                   },
                   "materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength: -2 "
                   "is negative or not finite"},
        BrokenCase{"NegativeEmissiveFactor",
                   [](GltfBuilder& g) {
                       g.doc["materials"] = {{{"emissiveFactor", {1, -1, 1}}}};
                   },
                   "materials[0].emissiveFactor[1]: -1 is negative or not finite"},
        BrokenCase{"BadSpectralExtension",
                   [](GltfBuilder& g) {
                       g.doc["materials"] = {{{"extensions",
                                               {{kSpectralExtensionName,
                                                 {{"reflectance", {{"rgb", {1.5, 0, 0}}}}}}}}}};
                   },
                   "broken.gltf: materials[0].extensions.DAISY_materials_spectral"},
        BrokenCase{"CameraFov",
                   [](GltfBuilder& g) {
                       g.doc["nodes"][0]["camera"] = 0;
                       g.doc["cameras"] = {{{"type", "perspective"},
                                            {"perspective", {{"yfov", 4}, {"znear", 0.1}}}}};
                   },
                   "cameras[0].perspective.yfov: 4 is outside (0, pi)"}),
    [](const ::testing::TestParamInfo<BrokenCase>& testInfo) {
        return std::string(testInfo.param.name);
    });

TEST(GltfLoaderErrors, MalformedJson) {
    const auto path = test::writeFile(test::testTempDir(), "malformed.gltf", "{ \"asset\": [1, ");
    EXPECT_GT(loadError(path).size(), path.size() + 2);
}

TEST(GltfLoaderErrors, MissingFile) {
    const auto path = (test::testTempDir() / "absent.gltf").string();
    EXPECT_EQ(loadError(path), path + ": cannot open the file");
}

TEST(GltfLoaderErrors, TruncatedGlb) {
    GltfBuilder gltf;
    gltf.addSingleTriangleScene(kUnitTriangle);
    const std::string bytes = gltf.glbBytes();
    const auto dir = test::testTempDir();
    loadError(test::writeFile(dir, "short.glb", bytes.substr(0, 16)));
    loadError(test::writeFile(dir, "cut.glb", bytes.substr(0, bytes.size() - 8)));
}

}  // namespace
}  // namespace daisy
