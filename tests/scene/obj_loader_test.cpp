#include "scene/obj_loader.h"

#include <gtest/gtest.h>

#include <string>

#include "test_util.h"

namespace daisy {
namespace {

// Asserts `scene` loaded and returns it.
Scene loadOk(const std::string& path, MtlConvention convention = MtlConvention::Standard) {
    auto scene = loadObj(path, convention);
    EXPECT_TRUE(scene.ok()) << scene.error().message;
    return scene.ok() ? std::move(scene).value() : Scene{};
}

std::string loadError(const std::string& path, MtlConvention convention = MtlConvention::Standard) {
    auto scene = loadObj(path, convention);
    EXPECT_FALSE(scene.ok()) << path << " loaded";
    return scene.ok() ? std::string() : scene.error().message;
}

Vec3d faceNormal(const Scene& scene, std::size_t t) {
    return normalize(
        areaVector2(scene.mesh.corner(t, 0), scene.mesh.corner(t, 1), scene.mesh.corner(t, 2)));
}

const char* const kTwoMaterialMtl = R"(newmtl red
Kd 0.8 0.1 0.1
Ks 0.1 0.9 0.2
newmtl lamp
Kd 0 0 0
Ke 5 4 3
newmtl warm
Kd 0.5 0.5 0.5
Ke 1 0.5 0
)";

const char* const kTwoMaterialObj = R"(mtllib scene.mtl
v 0 0 0
v 1 0 0
v 0 1 0
v 1 1 0
o floor
usemtl red
f 1 2 3
o light
usemtl lamp
f 2 4 3
usemtl warm
f 1 3 2
)";

TEST(ObjLoader, QuadBecomesTwoTrianglesAlongTheShorterDiagonal) {
    // Diagonal 1-3 has length^2 2, diagonal 2-4 has 10: tinyobjloader splits along the shorter
    // one, giving (1, 2, 3) and (1, 3, 4) in file numbering.
    const auto path = test::writeFile(test::testTempDir(), "quad.obj",
                                      "v 0 0 0\nv 3 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    const Scene scene = loadOk(path);
    EXPECT_EQ(scene.path, path);
    ASSERT_EQ(scene.mesh.positions.size(), 4u);
    EXPECT_EQ(scene.mesh.positions[1], Vec3d(3, 0, 0));
    ASSERT_EQ(scene.mesh.triangleCount(), 2u);
    EXPECT_EQ(scene.mesh.triangles[0], (std::array<uint32_t, 3>{0, 1, 2}));
    EXPECT_EQ(scene.mesh.triangles[1], (std::array<uint32_t, 3>{0, 2, 3}));
    // Trapezoid area (3 + 1) / 2 x 1 = 2.
    EXPECT_DOUBLE_EQ(meshArea(scene.mesh), 2.0);
    // No MTL: every face uses the one appended 0.8 grey default material.
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].name, "default");
    EXPECT_EQ(scene.materials[0].baseColor, (std::array<double, 3>{0.8, 0.8, 0.8}));
    EXPECT_EQ(scene.mesh.materials, (std::vector<uint32_t>{0, 0}));
}

TEST(ObjLoader, PentagonBecomesThreeTrianglesWithItsArea) {
    // Convex pentagon, counter-clockwise seen from +z. Shoelace area:
    // 0.5 * |sum(x_i y_{i+1} - x_{i+1} y_i)| = 0.5 * (0 + 3 + 7.5 + 4.5 + 0) = 7.5.
    const auto path = test::writeFile(test::testTempDir(), "pentagon.obj",
                                      "v 0 0 0\nv 2 0 0\nv 3 1.5 0\nv 1 3 0\nv -1 1.5 0\n"
                                      "f 1 2 3 4 5\n");
    const Scene scene = loadOk(path);
    ASSERT_EQ(scene.mesh.triangleCount(), 3u);
    double area = 0;
    for (std::size_t t = 0; t < 3; ++t) {
        const double triangle =
            triangleArea(scene.mesh.corner(t, 0), scene.mesh.corner(t, 1), scene.mesh.corner(t, 2));
        EXPECT_GT(triangle, 0) << t;
        area += triangle;
        // The winding of the polygon is kept: every triangle faces +z.
        EXPECT_NEAR(faceNormal(scene, t).z, 1.0, 1e-12) << t;
    }
    EXPECT_NEAR(area, 7.5, 1e-12);
}

TEST(ObjLoader, KdAndKeFromMtl) {
    const auto dir = test::testTempDir();
    test::writeFile(dir, "scene.mtl", kTwoMaterialMtl);
    const auto path = test::writeFile(dir, "scene.obj", kTwoMaterialObj);
    const Scene scene = loadOk(path);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    ASSERT_EQ(scene.materials.size(), 3u);  // every face has a material: no default
    const Material& red = scene.materials[0];
    EXPECT_EQ(red.name, "red");
    EXPECT_EQ(red.origin, path + ": material 'red'");
    EXPECT_EQ(red.baseColor, (std::array<double, 3>{0.8, 0.1, 0.1}));
    EXPECT_EQ(red.emissiveRgb, (std::array<double, 3>{0, 0, 0}));
    EXPECT_FALSE(red.spectral.fluorescence);  // the standard convention ignores Ks
    const Material& lamp = scene.materials[1];
    EXPECT_EQ(lamp.baseColor, (std::array<double, 3>{0, 0, 0}));
    EXPECT_EQ(lamp.emissiveRgb, (std::array<double, 3>{5, 4, 3}));
    EXPECT_FALSE(lamp.spectral.emission);
    // Shapes in file order, faces in order, each with its usemtl material.
    ASSERT_EQ(scene.mesh.triangleCount(), 3u);
    EXPECT_EQ(scene.mesh.triangles[0], (std::array<uint32_t, 3>{0, 1, 2}));
    EXPECT_EQ(scene.mesh.triangles[1], (std::array<uint32_t, 3>{1, 3, 2}));
    EXPECT_EQ(scene.mesh.triangles[2], (std::array<uint32_t, 3>{0, 2, 1}));
    EXPECT_EQ(scene.mesh.materials, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(ObjLoader, DaisyRiotConvention) {
    const auto dir = test::testTempDir();
    test::writeFile(dir, "scene.mtl", kTwoMaterialMtl);
    const auto path = test::writeFile(dir, "scene.obj", kTwoMaterialObj);
    const Scene scene = loadOk(path, MtlConvention::DaisyRiot);
    ASSERT_EQ(scene.materials.size(), 3u);
    // Ks is the fluorescent colour.
    const Material& red = scene.materials[0];
    ASSERT_TRUE(red.spectral.fluorescence);
    EXPECT_EQ(std::get<FluorescentColor>(*red.spectral.fluorescence).rgb,
              (std::array<double, 3>{0.1, 0.9, 0.2}));
    EXPECT_EQ(red.baseColor, (std::array<double, 3>{0.8, 0.1, 0.1}));
    // Black Kd with Ke (5, 4, 3) is a UV lamp: blacklight scaled by max(Ke) = 5, no RGB emission.
    const Material& lamp = scene.materials[1];
    ASSERT_TRUE(lamp.spectral.emission);
    EXPECT_EQ(std::get<PresetSpectrum>(lamp.spectral.emission->shape).name, "blacklight");
    EXPECT_EQ(lamp.spectral.emission->scale, 5.0);
    EXPECT_EQ(lamp.emissiveRgb, (std::array<double, 3>{0, 0, 0}));
    EXPECT_TRUE(lamp.isEmissive());
    EXPECT_FALSE(lamp.spectral.fluorescence);
    // A non-black Kd keeps its Ke as ordinary RGB emission.
    const Material& warm = scene.materials[2];
    EXPECT_FALSE(warm.spectral.emission);
    EXPECT_EQ(warm.emissiveRgb, (std::array<double, 3>{1, 0.5, 0}));
}

TEST(ObjLoader, FacesWithoutMaterialShareOneDefault) {
    const auto dir = test::testTempDir();
    test::writeFile(dir, "scene.mtl", "newmtl red\nKd 1 0 0\n");
    const auto path = test::writeFile(dir, "scene.obj",
                                      "mtllib scene.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                      "f 1 2 3\nusemtl red\nf 1 3 2\nusemtl blue\nf 3 2 1\n");
    const Scene scene = loadOk(path);
    ASSERT_EQ(scene.materials.size(), 2u);
    EXPECT_EQ(scene.materials[1].name, "default");
    EXPECT_EQ(scene.mesh.materials, (std::vector<uint32_t>{1, 0, 1}));
    // "blue" is not in the MTL: tinyobjloader's warning is passed on, prefixed with the path.
    ASSERT_FALSE(scene.warnings.empty());
    EXPECT_EQ(scene.warnings[0].rfind(path + ": ", 0), 0u) << scene.warnings[0];
}

TEST(ObjLoader, RelativeIndicesResolve) {
    const auto path = test::writeFile(test::testTempDir(), "relative.obj",
                                      "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n");
    const Scene scene = loadOk(path);
    ASSERT_EQ(scene.mesh.triangleCount(), 1u);
    EXPECT_EQ(scene.mesh.triangles[0], (std::array<uint32_t, 3>{0, 1, 2}));
}

TEST(ObjLoader, OutOfRangeVertexIndex) {
    const auto path = test::writeFile(test::testTempDir(), "bad.obj",
                                      "o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 99\n");
    EXPECT_EQ(loadError(path),
              path + ": shape 'tri' face 2: vertex index 99 is out of range (3 vertices)");
}

TEST(ObjLoader, RelativeIndexBeforeTheFirstVertex) {
    // -5 with 3 vertices resolves to vertex -1 (OBJ: negative indices count back from the end).
    const auto path =
        test::writeFile(test::testTempDir(), "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -5 1 2\n");
    EXPECT_EQ(loadError(path),
              path +
                  ": shape (unnamed) face 1: a relative vertex index reaches "
                  "before vertex 1 (3 vertices)");
}

TEST(ObjLoader, ReaderErrorsNameTheFile) {
    // Index 0 does not exist in OBJ (indices start at 1); tinyobjloader refuses the line.
    const auto path =
        test::writeFile(test::testTempDir(), "zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    const std::string message = loadError(path);
    EXPECT_EQ(message.rfind(path + ":4: f: '0' is not a vertex reference", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(ObjLoader, NonFiniteVertexNamesItsLine) {
    // 1e999 overflows a double to infinity.
    const auto path = test::writeFile(test::testTempDir(), "inf.obj",
                                      "# comment\nv 0 0 0\n\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string message = loadError(path);
    EXPECT_EQ(message.rfind(path + ":4: v: '1e999' is not a finite number", 0), 0u) << message;
}

TEST(ObjLoader, BadMtlValues) {
    const auto dir = test::testTempDir();
    const auto path = test::writeFile(dir, "scene.obj",
                                      "mtllib scene.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                      "usemtl hot\nf 1 2 3\n");
    test::writeFile(dir, "scene.mtl", "newmtl hot\nKd 1.5 0 0\n");
    EXPECT_EQ(loadError(path),
              path + ": material 'hot': Kd 1.5 0 0: components must each be in [0, 1]");

    test::writeFile(dir, "scene.mtl", "newmtl hot\nKd 0.5 0.5 0.5\nKe 1 -1 0\n");
    EXPECT_EQ(loadError(path),
              path + ": material 'hot': Ke 1 -1 0: components must be finite and >= 0");

    // Ks is only read, and so only checked, in the DaisyRiot convention.
    test::writeFile(dir, "scene.mtl", "newmtl hot\nKd 0.5 0.5 0.5\nKs 2 0 0\n");
    EXPECT_EQ(loadError(path, MtlConvention::DaisyRiot),
              path + ": material 'hot': Ks 2 0 0: components must each be in [0, 1]");
    const Scene scene = loadOk(path, MtlConvention::Standard);
    EXPECT_FALSE(scene.materials[0].spectral.fluorescence);
}

TEST(ObjLoader, MissingMtlIsAWarning) {
    const auto path = test::writeFile(test::testTempDir(), "scene.obj",
                                      "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                      "usemtl red\nf 1 2 3\n");
    const Scene scene = loadOk(path);
    ASSERT_EQ(scene.mesh.triangleCount(), 1u);
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].name, "default");
    bool named = false;
    for (const std::string& warning : scene.warnings) {
        EXPECT_EQ(warning.rfind(path + ": ", 0), 0u) << warning;
        named = named || warning.find("missing.mtl") != std::string::npos;
    }
    EXPECT_TRUE(named) << "no warning names missing.mtl";
}

TEST(ObjLoader, MissingObjFileIsAnError) {
    const std::string path = (test::testTempDir() / "absent.obj").string();
    EXPECT_EQ(loadError(path), path + ": no such file");
}

}  // namespace
}  // namespace daisy
