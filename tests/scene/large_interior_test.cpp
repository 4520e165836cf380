// The large interior of tools/make_large_interior.py (docs/performance.md, "Large interior"),
// generated here at small sizes: the loader reads what the generator promises (its triangle
// count within 0.1% of --triangles, every triangle with area, every material doubleSided under
// reflectance 1, the camera inside, the emitters outside the openings they light the hall
// through, four point lights), the count follows the parameter, the same arguments give the same
// bytes, and the all-pairs matrix is refused over --max-memory in one line. Blender's own export
// of the small size (tools/blender_reexport.py, committed as tests/data/blender/
// interior_small.glb) loads as the same scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "scene/load_scene.h"
#include "test_util.h"

namespace daisy {
namespace {

// Runs the generator for `triangles` into `path`; its output, or a failure with it.
void generate(int triangles, const std::filesystem::path& path) {
    const std::string command = std::string(DAISY_PYTHON) + " " + DAISY_TOOLS_DIR +
        "/make_large_interior.py --triangles " + std::to_string(triangles) + " -o '" +
        path.string() + "' 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    char buffer[4096];
    while (std::size_t count = fread(buffer, 1, sizeof buffer, pipe))
        output.append(buffer, count);
    ASSERT_EQ(pclose(pipe), 0) << command << "\n" << output;
}

Scene load(const std::filesystem::path& path) {
    auto scene = loadScene(path.string(), {});
    if (!scene) {
        ADD_FAILURE() << scene.error().message;
        return Scene{};
    }
    return std::move(*scene);
}

double triangleArea(const TriangleMesh& mesh, std::size_t t) {
    const Vec3d a = mesh.corner(t, 0), b = mesh.corner(t, 1), c = mesh.corner(t, 2);
    return 0.5 * length(cross(b - a, c - a));
}

Vec3d centroid(const TriangleMesh& mesh, std::size_t t) {
    return (mesh.corner(t, 0) + mesh.corner(t, 1) + mesh.corner(t, 2)) / 3.0;
}

// The hall of make_large_interior.py: x in [-6, 6], z in [-12, 12], the window wall at x = 6
// with openings z in [zc - 0.8, zc + 0.8] x y in [1.5, 5.5], the vault (radius 3.2 m over
// y = 8) open where |x| < 1 and |z| < 4.
constexpr double kHalfWidth = 6, kHalfDepth = 12, kSpring = 8, kVaultRadius = 3.2;
constexpr double kWindowZ[] = {-9, -3, 3, 9};

int materialNamed(const Scene& scene, const std::string& name) {
    for (std::size_t m = 0; m < scene.materials.size(); ++m)
        if (scene.materials[m].name == name) return static_cast<int>(m);
    ADD_FAILURE() << "no material " << name;
    return -1;
}

TEST(LargeInterior, LoadsWithWhatTheGeneratorPromises) {
    const auto path = test::testTempDir() / "interior.gltf";
    generate(6000, path);
    const Scene scene = load(path);
    const TriangleMesh& mesh = scene.mesh;
    EXPECT_NEAR(double(mesh.triangleCount()), 6000.0, 6.0);  // the generator's 0.1%
    EXPECT_EQ(scene.degenerateDropped, 0u);
    // Non-degenerate: the smallest triangles are the pendants' cords (1 cm radius), about
    // 1e-3 m^2 at this size; 1e-5 m^2 is far from float rounding at 12 m.
    double smallest = INFINITY;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
        smallest = std::min(smallest, triangleArea(mesh, t));
    EXPECT_GT(smallest, 1e-5);

    ASSERT_EQ(scene.materials.size(), 12u);
    std::set<std::string> emissive;
    for (const Material& material : scene.materials) {
        EXPECT_TRUE(material.doubleSided) << material.name;
        for (double channel : material.baseColor)
            EXPECT_LT(channel, 1.0) << material.name;
        if (material.isEmissive()) emissive.insert(material.name);
    }
    EXPECT_EQ(emissive, (std::set<std::string>{"bulb", "sky", "sun_sky"}));

    ASSERT_EQ(scene.cameras.size(), 1u);
    const Camera& camera = scene.cameras[0];
    EXPECT_LT(std::abs(camera.position.x), kHalfWidth);
    EXPECT_LT(std::abs(camera.position.z), kHalfDepth);
    EXPECT_GT(camera.position.y, 0.0);
    EXPECT_LT(camera.position.y, kSpring);
    EXPECT_GT(camera.forward.z, 0.5);  // up the hall

    ASSERT_EQ(scene.lights.size(), 4u);
    for (const PunctualLight& light : scene.lights) {
        EXPECT_EQ(light.type, PunctualLight::Type::Point);
        EXPECT_DOUBLE_EQ(light.intensity, 12.0);
        EXPECT_LT(light.position.x, -kHalfWidth + 0.5);  // the sconces on the wall at x = -6
    }

    // Light comes in through openings: the sky panels lie outside the window wall and the sun
    // panel above the vault's crown, and no wall or vault triangle fills an opening.
    const int sky = materialNamed(scene, "sky"), sun = materialNamed(scene, "sun_sky");
    const int plaster = materialNamed(scene, "plaster"), ceiling = materialNamed(scene, "ceiling");
    std::size_t skyTriangles = 0, sunTriangles = 0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const int material = static_cast<int>(mesh.materials[t]);
        const Vec3d c = centroid(mesh, t);
        if (material == sky) {
            ++skyTriangles;
            EXPECT_GT(c.x, kHalfWidth);
        } else if (material == sun) {
            ++sunTriangles;
            EXPECT_GT(c.y, kSpring + kVaultRadius);
        } else if (material == plaster && std::abs(c.x - kHalfWidth) < 1e-6) {
            for (double z : kWindowZ)
                EXPECT_FALSE(std::abs(c.z - z) < 0.8 && c.y > 1.5 && c.y < 5.5)
                    << "a wall triangle in the window at z = " << z;
        } else if (material == ceiling && c.y > kSpring + 1e-6) {
            EXPECT_FALSE(std::abs(c.x) < 1.0 && std::abs(c.z) < 4.0) << "the skylight is shut";
        }
    }
    EXPECT_EQ(skyTriangles, 8u);  // four panels of one quad
    EXPECT_EQ(sunTriangles, 2u);
}

TEST(LargeInterior, TriangleCountFollowsTheParameterAndIsDeterministic) {
    const auto dir = test::testTempDir();
    std::vector<std::size_t> counts;
    for (int triangles : {5000, 10000, 20000}) {
        const auto path = dir / ("interior_" + std::to_string(triangles) + ".gltf");
        generate(triangles, path);
        counts.push_back(load(path).mesh.triangleCount());
        EXPECT_NEAR(double(counts.back()), triangles, 0.001 * triangles);
    }
    // The same arguments, the same bytes (.gltf and its .bin).
    std::filesystem::create_directories(dir / "again");
    generate(5000, dir / "again" / "interior_5000.gltf");
    for (const char* name : {"interior_5000.gltf", "interior_5000.bin"})
        EXPECT_TRUE(test::readBytes(dir / "again" / name) == test::readBytes(dir / name)) << name;
    // A .glb holds the same scene.
    generate(5000, dir / "interior.glb");
    EXPECT_EQ(load(dir / "interior.glb").mesh.triangleCount(), counts[0]);
}

TEST(LargeInterior, InfoEstimatesTheMatrixAndAnAllPairsBuildIsRefusedInOneLine) {
    const auto dir = test::testTempDir();
    const auto path = dir / "interior.gltf";
    generate(5000, path);
    const test::RunResult info =
        test::runDaisy("info '" + path.string() + "' --max-memory 64M --transport matrix");
    EXPECT_EQ(info.status, 0) << info.output;
    // doubleSided: a back patch for each triangle.
    EXPECT_NE(info.output.find("patches        10,00"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("a form-factor build would be refused"), std::string::npos)
        << info.output;
    // `auto` (the default) takes the links where F does not fit: F is ~150 MiB here.
    const test::RunResult chosen = test::runDaisy("info '" + path.string() + "' --max-memory 64M");
    EXPECT_EQ(chosen.status, 0) << chosen.output;
    EXPECT_NE(chosen.output.find("transport      hierarchical (auto: the matrix F would need ~"),
              std::string::npos)
        << chosen.output;
    EXPECT_NE(chosen.output.find(", more than --max-memory 64.0 MiB)"), std::string::npos)
        << chosen.output;
    const test::RunResult roomy = test::runDaisy("info '" + path.string() + "'");
    EXPECT_NE(roomy.output.find("transport      matrix (auto: the matrix F, ~"), std::string::npos)
        << roomy.output;
    const auto matrix = dir / "F.mtx";
    const test::RunResult build = test::runDaisy("formfactors '" + path.string() +
                                                 "' --max-memory 64M -o '" + matrix.string() + "'");
    EXPECT_EQ(build.status, 2) << build.output;
    EXPECT_NE(build.output.find("error: " + path.string() + ": the view-factor matrix needs about"),
              std::string::npos)
        << build.output;
    EXPECT_NE(build.output.find("more than --max-memory 64"), std::string::npos) << build.output;
    EXPECT_FALSE(std::filesystem::exists(matrix));
}

TEST(LargeInterior, BlenderExportLoadsAsTheGeneratedScene) {
    const auto path = test::testTempDir() / "interior.gltf";
    generate(5000, path);
    const Scene ours = load(path);
    const Scene blender = load(test::testDataPath("blender/interior_small.glb"));
    ASSERT_EQ(blender.mesh.triangleCount(), ours.mesh.triangleCount());
    EXPECT_EQ(blender.degenerateDropped, 0u);
    // The same surfaces (Blender reorders the objects and materials): the area of each material.
    const auto areaOf = [](const Scene& scene, const std::string& name) {
        double area = 0;
        for (std::size_t t = 0; t < scene.mesh.triangleCount(); ++t)
            if (scene.materials[scene.mesh.materials[t]].name == name)
                area += triangleArea(scene.mesh, t);
        return area;
    };
    for (const Material& material : ours.materials) {
        const double area = areaOf(ours, material.name);
        EXPECT_NEAR(areaOf(blender, material.name), area, 1e-5 * area) << material.name;
    }
    for (const Material& material : blender.materials)
        EXPECT_TRUE(material.doubleSided) << material.name;
    ASSERT_EQ(blender.cameras.size(), 1u);
    const Vec3d shift = blender.cameras[0].position - ours.cameras[0].position;
    EXPECT_LT(length(shift), 1e-5);
    EXPECT_GT(dot(blender.cameras[0].forward, ours.cameras[0].forward), 1 - 1e-9);
    ASSERT_EQ(blender.lights.size(), 4u);
    for (const PunctualLight& light : blender.lights)
        EXPECT_NEAR(light.intensity, 12.0, 1e-3);  // cd -> W on import, W -> cd on export
}

}  // namespace
}  // namespace daisy
