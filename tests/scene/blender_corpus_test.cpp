// Files written by Blender 3.4's own glTF exporter (tools/make_blender_corpus.py,
// committed under tests/data/blender): what Blender put in them is what daisy loads, and the
// diffuse Cornell box renders like Cycles' render of the same scene.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "geometry/patch_mesh.h"
#include "image/image_io.h"
#include "scene/load_scene.h"
#include "scene/surface_appearance.h"
#include "spectral/color.h"
#include "test_util.h"

namespace daisy {
namespace {

Scene load(const std::string& name) {
    auto scene = loadScene(test::testDataPath("blender/" + name), {});
    if (!scene) {
        ADD_FAILURE() << scene.error().message;
        return Scene{};
    }
    return std::move(*scene);
}

int materialIndex(const Scene& scene, const std::string& name) {
    for (std::size_t m = 0; m < scene.materials.size(); ++m) {
        if (scene.materials[m].name == name) return static_cast<int>(m);
    }
    ADD_FAILURE() << "no material " << name;
    return 0;
}

// Area-weighted mean patch reflectance of material `name`.
std::array<double, 3> meanReflectance(const Scene& scene, const std::string& name) {
    auto patches = buildPatchMesh(scene.mesh, 0.25);
    EXPECT_TRUE(patches);
    const PatchAppearance appearance = patchAppearance(scene, *patches);
    // An untextured scene has no per-patch appearance: the test wants one.
    EXPECT_EQ(appearance.reflectance.size(), patches->patchCount());
    if (appearance.reflectance.size() != patches->patchCount()) return {0, 0, 0};
    const auto material = static_cast<uint32_t>(materialIndex(scene, name));
    std::array<double, 3> sum{0, 0, 0};
    double area = 0;
    for (std::size_t i = 0; i < patches->patchCount(); ++i) {
        if (patches->materials[i] != material) continue;
        for (int c = 0; c < 3; ++c)
            sum[c] += appearance.reflectance[i][c] * patches->areas[i];
        area += patches->areas[i];
    }
    for (double& c : sum)
        c /= area;
    return sum;
}

TEST(BlenderCorpus, RoomLoadsWhatBlenderWrote) {
    const Scene scene = load("room.gltf");
    // Seven quads (floor, painted wall, ceiling, three walls, the panel) and three nodes of one
    // cube mesh (12 triangles each).
    EXPECT_EQ(scene.mesh.triangleCount(), 7u * 2 + 3u * 12);
    EXPECT_EQ(scene.materials.size(), 6u);
    for (const Material& material : scene.materials)
        EXPECT_TRUE(material.doubleSided) << material.name;  // Blender's default
    // Blender's specular 0 and ior (KHR_materials_specular, _ior) change nothing diffuse.
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    ASSERT_EQ(scene.cameras.size(), 1u);

    // The floor: a checkerboard whose squares Blender's byte image stores as the sRGB codes
    // of 0.8 and (0.1, 0.3, 0.6) (what the script assigns), so the floor's mean reflectance is
    // the average of their decoded values (IEC 61966-2-1); the 16 x 16 sample grid per patch
    // aligns with the squares' edges to within ~0.5% (tolerance 0.005).
    const Material& floor = scene.materials[materialIndex(scene, "floor")];
    ASSERT_TRUE(floor.baseColorTexture.has_value());
    EXPECT_EQ(floor.baseColor, (std::array<double, 3>{1, 1, 1}));  // the default factor
    const auto decoded = [](double code) { return srgbDecode(std::round(code * 255) / 255); };
    const auto checker = meanReflectance(scene, "floor");
    EXPECT_NEAR(checker[0], 0.5 * (decoded(0.8) + decoded(0.1)), 0.005);
    EXPECT_NEAR(checker[1], 0.5 * (decoded(0.8) + decoded(0.3)), 0.005);
    EXPECT_NEAR(checker[2], 0.5 * (decoded(0.8) + decoded(0.6)), 0.005);
    // The painted wall: COLOR_0 red (0.8, 0.1, 0.1) at the floor to blue at the ceiling, linear
    // in height, so its mean is the average of the two.
    ASSERT_FALSE(scene.vertexColors.empty());
    const auto painted = meanReflectance(scene, "painted");
    EXPECT_NEAR(painted[0], 0.45, 1e-3);
    EXPECT_NEAR(painted[1], 0.10, 1e-3);
    EXPECT_NEAR(painted[2], 0.45, 1e-3);

    // The emissive panel: Blender's Emission Strength 5 is emissiveStrength 5 (nits).
    const Material& panel = scene.materials[materialIndex(scene, "panel")];
    EXPECT_NEAR(panel.emissiveRgb[0], 5 * std::numbers::pi, 1e-6);
    EXPECT_NEAR(panel.emissiveRgb[1], 5 * 0.9 * std::numbers::pi, 1e-5);

    // KHR_lights_punctual: Blender writes W x 683 / (4 pi) candela (100 W, 200 W).
    ASSERT_EQ(scene.lights.size(), 2u);
    const PunctualLight& point = scene.lights[0];
    EXPECT_EQ(point.type, PunctualLight::Type::Point);
    EXPECT_NEAR(point.intensity, 100 * 683 / (4 * std::numbers::pi), 1e-6);
    EXPECT_NEAR(point.color[1], 0.8, 1e-6);
    // Blender (1, 4, 2) z-up is glTF (1, 2, -4) y-up.
    EXPECT_NEAR(length(point.position - Vec3d{1, 2, -4}), 0, 1e-6);
    const PunctualLight& spot = scene.lights[1];
    EXPECT_EQ(spot.type, PunctualLight::Type::Spot);
    EXPECT_NEAR(spot.outerConeRad, 0.5 * 60 * std::numbers::pi / 180, 1e-6);  // spot_size / 2
    // Rotated 30 degrees about Blender's x from straight down: down and towards Blender +y.
    EXPECT_NEAR(spot.direction.y, -std::cos(std::numbers::pi / 6), 1e-6);
    EXPECT_NEAR(spot.direction.z, -std::sin(std::numbers::pi / 6), 1e-6);
}

// Mean of the channel named `name` (EXR files list channels alphabetically) over the image.
double channelMean(const Image& image, const std::string& name) {
    int c = -1;
    for (std::size_t k = 0; k < image.channelNames.size(); ++k) {
        if (image.channelNames[k] == name) c = static_cast<int>(k);
    }
    EXPECT_GE(c, 0) << "no channel " << name;
    if (c < 0) return 0;
    double sum = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x)
            sum += image.at(x, y)[c];
    }
    return sum / (double(image.width) * image.height);
}

TEST(BlenderCorpus, CornellBoxMatchesCycles) {
    // cornell_cycles.exr: Cycles, Lambertian copies of the exported materials, 1024 samples,
    // 32 bounces (tools/make_blender_corpus.py). daisy renders the exported file at the same
    // 64 x 64 through the same camera; both are linear radiance (emissive strength 10 = 10).
    // Tolerance 4% per channel on the image mean (measured: within 2%): daisy solves 31 wavelength
    // samples with upsampled RGB reflectances where Cycles multiplies RGB, and Cycles' 1024 samples
    // leave ~1% noise.
    const auto dir = test::testTempDir();
    const std::string out = (dir / "cornell.exr").string();
    const test::RunResult run =
        test::runDaisy("render " + test::testDataPath("blender/cornell.gltf") +
                       " --width 64 --height 64 -q -o " + out);
    ASSERT_EQ(run.status, 0) << run.output;
    auto daisyImage = readExr(out);
    ASSERT_TRUE(daisyImage) << daisyImage.error().message;
    auto cycles = readExr(test::testDataPath("blender/cornell_cycles.exr"));
    ASSERT_TRUE(cycles) << cycles.error().message;
    ASSERT_EQ(cycles->width, 64);
    ASSERT_EQ(daisyImage->width, 64);
    for (const char* channel : {"R", "G", "B"}) {
        const double expected = channelMean(*cycles, channel);
        const double got = channelMean(*daisyImage, channel);
        EXPECT_NEAR(got / expected, 1.0, 0.04)
            << channel << ": daisy " << got << ", Cycles " << expected;
    }
}

TEST(BlenderCorpus, GltfpackOutputLoadsLikeTheOriginal) {
    // room_packed.gltf: `gltfpack -i room.gltf -o room_packed.gltf -mi` (gltfpack 1.3, npm):
    // KHR_mesh_quantization (UNSIGNED_SHORT positions, dequantized by the node transform),
    // KHR_texture_transform (quantized uvs), and the three cubes as one node with
    // EXT_mesh_gpu_instancing. Same triangles, lights and floor texture mean as the original;
    // positions within gltfpack's 14-bit quantization (bounds to 1e-3 of the 5 m room).
    const Scene original = load("room.gltf");
    const Scene packed = load("room_packed.gltf");
    EXPECT_EQ(packed.mesh.triangleCount(), original.mesh.triangleCount());
    EXPECT_NEAR(meshArea(packed.mesh), meshArea(original.mesh), 1e-2);
    const Bounds3d a = meshBounds(original.mesh), b = meshBounds(packed.mesh);
    EXPECT_NEAR(length(a.lo - b.lo), 0, 1e-3);
    EXPECT_NEAR(length(a.hi - b.hi), 0, 1e-3);
    ASSERT_EQ(packed.lights.size(), 2u);
    EXPECT_NEAR(packed.lights[0].intensity, original.lights[0].intensity, 1e-3);
    const auto expected = meanReflectance(original, "floor");
    const auto got = meanReflectance(packed, "floor");
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], expected[c], 0.005) << c;
}

TEST(BlenderCorpus, MeshoptCompressedFileLoadsLikeTheUncompressedOne) {
    // room_meshopt.glb: the same with `-cc` (EXT_meshopt_compression, required; GLB with the
    // texture inside), decoded by libmeshoptimizer into the quantized data room_packed.gltf
    // holds, so the scene matches it: triangles, bounds (to 1e-4 m), lights and the texture.
    const Scene packed = load("room_packed.gltf");
    const Scene compressed = load("room_meshopt.glb");
    EXPECT_EQ(compressed.mesh.triangleCount(), packed.mesh.triangleCount());
    const Bounds3d a = meshBounds(packed.mesh), b = meshBounds(compressed.mesh);
    EXPECT_NEAR(length(a.lo - b.lo), 0, 1e-4);
    EXPECT_NEAR(length(a.hi - b.hi), 0, 1e-4);
    EXPECT_NEAR(meshArea(compressed.mesh), meshArea(packed.mesh), 1e-3);  // of 99.5 m^2
    ASSERT_EQ(compressed.lights.size(), 2u);
    EXPECT_NEAR(compressed.lights[1].intensity, packed.lights[1].intensity, 1e-3);
    const auto expected = meanReflectance(packed, "floor");
    const auto got = meanReflectance(compressed, "floor");
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], expected[c], 1e-3) << c;
}

// cornell_draco.gltf: cornell.gltf with every primitive KHR_draco_mesh_compression-compressed
// (required) by draco_transcoder 1.5.5 at its default 11-bit positions
// (tools/make_draco_fixture.py), decoded by libdraco. Each primitive is quantized over its own
// bounds, at most the 1 m box, so a corner moves by at most one step of 1/2047 m.
constexpr double kDracoStep = 1.0 / 2047;

// True when triangle t of `a` and triangle u of `b` have the same material and the same corners
// within `tolerance`, in the same winding (any starting corner).
bool sameTriangle(const TriangleMesh& a, std::size_t t, const TriangleMesh& b, std::size_t u,
                  double tolerance) {
    if (a.materials[t] != b.materials[u]) return false;
    for (int shift = 0; shift < 3; ++shift) {
        bool all = true;
        for (int k = 0; k < 3 && all; ++k)
            all = length(a.corner(t, k) - b.corner(u, (k + shift) % 3)) <= tolerance;
        if (all) return true;
    }
    return false;
}

TEST(BlenderCorpus, DracoCompressedCornellBoxLoadsLikeTheUncompressedOne) {
    const Scene original = load("cornell.gltf");
    const Scene draco = load("cornell_draco.gltf");
    ASSERT_EQ(original.mesh.triangleCount(), 36u);
    ASSERT_EQ(draco.mesh.triangleCount(), original.mesh.triangleCount());
    ASSERT_EQ(draco.materials.size(), original.materials.size());
    // Materials and the emitter come from the same JSON (emissive strength 10 included).
    for (std::size_t m = 0; m < original.materials.size(); ++m) {
        EXPECT_EQ(draco.materials[m].name, original.materials[m].name);
        EXPECT_EQ(draco.materials[m].baseColor, original.materials[m].baseColor);
        EXPECT_EQ(draco.materials[m].emissiveRgb, original.materials[m].emissiveRgb);
    }
    ASSERT_EQ(original.materials[3].name, "light");
    EXPECT_GT(draco.materials[3].emissiveRgb[0], 0.0);
    // Every decoded triangle is one of the original's, corner by corner within the step, and no
    // two decoded triangles match the same original one.
    std::vector<char> used(original.mesh.triangleCount(), 0);
    double worst = 0;
    for (std::size_t t = 0; t < draco.mesh.triangleCount(); ++t) {
        std::size_t match = original.mesh.triangleCount();
        for (std::size_t u = 0; u < original.mesh.triangleCount() && match == used.size(); ++u) {
            if (!used[u] && sameTriangle(draco.mesh, t, original.mesh, u, kDracoStep)) match = u;
        }
        ASSERT_LT(match, used.size()) << "decoded triangle " << t << " is not in cornell.gltf";
        used[match] = 1;
        for (int k = 0; k < 3; ++k) {
            double nearest = 1e30;
            for (int j = 0; j < 3; ++j) {
                nearest = std::min(
                    nearest, length(draco.mesh.corner(t, k) - original.mesh.corner(match, j)));
            }
            worst = std::max(worst, nearest);
        }
    }
    EXPECT_GT(worst, 0.0);  // quantized: not a copy of the original floats
    EXPECT_LE(worst, kDracoStep);
    EXPECT_NEAR(meshArea(draco.mesh), meshArea(original.mesh), 6.19 * 4 * kDracoStep);
}

TEST(BlenderCorpus, DracoCompressedCornellBoxRendersLikeCycles) {
    // The same render and tolerance as CornellBoxMatchesCycles, from the Draco file.
    const auto dir = test::testTempDir();
    const std::string out = (dir / "cornell_draco.exr").string();
    const test::RunResult run =
        test::runDaisy("render " + test::testDataPath("blender/cornell_draco.gltf") +
                       " --width 64 --height 64 -q -o " + out);
    ASSERT_EQ(run.status, 0) << run.output;
    auto daisyImage = readExr(out);
    ASSERT_TRUE(daisyImage) << daisyImage.error().message;
    auto cycles = readExr(test::testDataPath("blender/cornell_cycles.exr"));
    ASSERT_TRUE(cycles) << cycles.error().message;
    ASSERT_EQ(daisyImage->width, 64);
    for (const char* channel : {"R", "G", "B"}) {
        const double expected = channelMean(*cycles, channel);
        const double got = channelMean(*daisyImage, channel);
        EXPECT_NEAR(got / expected, 1.0, 0.04)
            << channel << ": daisy " << got << ", Cycles " << expected;
    }
}

// A copy of cornell_draco.gltf in a temporary folder, edited by `edit`, with `bin` as its
// buffer; the loader's one-line error.
// The copy's path.
std::string dracoCopyPath() {
    return (test::testTempDir() / "cornell_draco.gltf").string();
}

std::string dracoError(const std::function<void(nlohmann::json&)>& edit, const std::string& bin) {
    std::ifstream in(test::testDataPath("blender/cornell_draco.gltf"));
    nlohmann::json doc = nlohmann::json::parse(in);
    edit(doc);
    const auto dir = test::testTempDir();
    test::writeFile(dir, "cornell_draco.bin", bin);
    const std::string path = test::writeFile(dir, "cornell_draco.gltf", doc.dump());
    auto scene = loadScene(path, {});
    if (scene) return "loaded";
    return scene.error().message;
}

std::string dracoBin() {
    std::ifstream in(test::testDataPath("blender/cornell_draco.bin"), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(BlenderCorpus, CorruptDracoDataIsRefusedNamingTheMeshAndPrimitive) {
    const std::string where =
        ": meshes[0] (\"floor\").primitives[0].extensions.KHR_draco_mesh_compression: ";
    const std::string path = dracoCopyPath();
    const auto keep = [](nlohmann::json&) {};
    // Zeros: no Draco header.
    EXPECT_EQ(dracoError(keep, std::string(dracoBin().size(), '\0')),
              path + where +
                  "the compressed data in bufferViews[0] cannot be decoded (draco: Not "
                  "a Draco file.)");
    // The header kept, the geometry overwritten.
    std::string bin = dracoBin();
    for (std::size_t i = 20; i < 60; ++i)
        bin[i] = 'Z';
    EXPECT_EQ(dracoError(keep, bin),
              path + where +
                  "the compressed data in bufferViews[0] cannot be decoded (draco: "
                  "Failed to decode geometry data.)");
    // An attribute id the compressed data does not have.
    EXPECT_EQ(
        dracoError(
            [](nlohmann::json& doc) {
                doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]
                   ["attributes"]["POSITION"] = 7;
            },
            dracoBin()),
        path + where + "attribute POSITION: Draco attribute id 7 is not in the compressed data");
    // Accessor counts that do not match the decoded mesh (2 triangles over 4 points).
    EXPECT_EQ(dracoError(
                  [](nlohmann::json& doc) {
                      const int indices = doc["meshes"][0]["primitives"][0]["indices"];
                      doc["accessors"][indices]["count"] = 9;
                  },
                  dracoBin()),
              path + where +
                  "indices accessor 0 has count 9 but the decoded mesh has 2 triangles (6 "
                  "indices)");
    EXPECT_EQ(dracoError(
                  [](nlohmann::json& doc) {
                      const int position =
                          doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
                      doc["accessors"][position]["count"] = 3;
                  },
                  dracoBin()),
              path + where +
                  "attribute POSITION: accessor 1 has count 3 but the decoded mesh has 4 points");
    // A bufferView past the end of the buffer.
    EXPECT_EQ(dracoError([](nlohmann::json& doc) { doc["bufferViews"][0]["byteLength"] = 100000; },
                         dracoBin()),
              path + where + "bufferViews[0]: bytes [0, 100000) exceed buffers[0] (664 bytes)");
}

TEST(BlenderCorpus, DracoCorruptionFuzzNeverCrashes) {
    // Every third byte of the compressed data set to 0xA5 in turn: each load either succeeds or
    // gives one line naming the file.
    const std::string original = dracoBin();
    const std::string path = dracoCopyPath();
    for (std::size_t i = 0; i < original.size(); i += 3) {
        std::string bin = original;
        bin[i] = char(0xA5);
        const std::string message = dracoError([](nlohmann::json&) {}, bin);
        if (message == "loaded") continue;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << i << ": " << message;
    }
}

}  // namespace
}  // namespace daisy
