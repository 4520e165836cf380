// Runs `daisy render` (DESIGN.md sections 7 and 9, docs/rendering.md): output formats, the
// white furnace's exact radiance, the automatic patch size and --subdivide 0, exit statuses and
// no partial file on failure.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "image/image_io.h"
#include "spectral/color.h"
#include "spectral/wavelength_set.h"
#include "test_util.h"

namespace daisy {
namespace {

using test::runDaisy;
using test::RunResult;

const std::string kFurnace = test::assetPath("scenes/furnace_box.gltf");

std::size_t fileCount(const std::filesystem::path& dir) {
    std::size_t count = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir))
        ++count;
    return count;
}

// The white furnace (tools/make_analytic_scenes.py): a closed cube, flat reflectance 0.5 and
// flat emission 1, so B = E / (1 - rho) = 2 at every wavelength and every pixel's radiance is
// B / pi. The PFM holds linear sRGB without exposure: the sRGB of XYZ = toXyz(flat 2 / pi) on
// the `auto` set (the scene has no UV light), to the row sums' accuracy (1e-3 with hybrid L = 1
// on 12 triangles; 2% allowed for the quadrature of the cube's corners).
TEST(RenderCli, FurnaceBoxIsUniformAtTheExactRadiance) {
    const auto dir = test::testTempDir();
    const std::string out = (dir / "furnace.pfm").string();
    const RunResult run = runDaisy("render " + kFurnace + " -o " + out + " --width 32 --height 24");
    ASSERT_EQ(run.status, 0) << run.output;
    auto image = readPfm(out);
    ASSERT_TRUE(image) << image.error().message;
    ASSERT_EQ(image->width, 32);
    ASSERT_EQ(image->height, 24);

    auto set = makeWavelengthSet(WavelengthSpec{});
    ASSERT_TRUE(set);
    const std::vector<double> radiance(set->size(), 2.0 / std::numbers::pi);
    const Rgb expected = xyzToLinearSrgb(set->toXyz(radiance));
    for (int y = 0; y < image->height; ++y) {
        for (int x = 0; x < image->width; ++x) {
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(image->at(x, y)[c], expected[c], 0.02 * expected[c]) << x << "," << y;
        }
    }
    EXPECT_NE(run.output.find("render: wrote"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("peak memory"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("automatic --subdivide"), std::string::npos) << run.output;
}

// The same furnace through the final gather (every surface is a light: the direct part comes
// out of B and back per sample) and through the path tracer (its mean within 2%: each pixel's
// noise at 64 spp is a few percent).
TEST(RenderCli, FurnaceBoxThroughTheGatherAndThePathTracer) {
    const auto dir = test::testTempDir();
    auto set = makeWavelengthSet(WavelengthSpec{});
    ASSERT_TRUE(set);
    const std::vector<double> radiance(set->size(), 2.0 / std::numbers::pi);
    const Rgb expected = xyzToLinearSrgb(set->toXyz(radiance));
    for (const std::string mode : {"--gather direct", "--integrator path --spp 64"}) {
        const std::string out = (dir / "furnace.pfm").string();
        const RunResult run =
            runDaisy("render " + kFurnace + " -o " + out + " --width 16 --height 12 " + mode);
        ASSERT_EQ(run.status, 0) << run.output;
        auto image = readPfm(out);
        ASSERT_TRUE(image) << image.error().message;
        Rgb mean{0, 0, 0};
        const double pixels = double(image->width) * image->height;
        for (int y = 0; y < image->height; ++y) {
            for (int x = 0; x < image->width; ++x) {
                for (int c = 0; c < 3; ++c)
                    mean[c] += image->at(x, y)[c] / pixels;
            }
        }
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(mean[c], expected[c], 0.02 * expected[c]) << mode;
        if (mode.find("path") != std::string::npos) {
            EXPECT_NE(run.output.find("path traced, 64 spp"), std::string::npos) << run.output;
            EXPECT_NE(run.output.find("noise: relative RMS"), std::string::npos) << run.output;
        } else {
            EXPECT_NE(run.output.find("final gather"), std::string::npos) << run.output;
        }
    }
}

TEST(RenderCli, WritesPngExrAndSpectralExr) {
    const auto dir = test::testTempDir();
    const std::string base = "render " + kFurnace + " --width 16 --height 12 -q --subdivide 0.5";
    ASSERT_EQ(runDaisy(base + " -o " + (dir / "a.png").string()).status, 0);
    auto png = readPng((dir / "a.png").string());
    ASSERT_TRUE(png) << png.error().message;
    EXPECT_EQ(png->width, 16);

    ASSERT_EQ(runDaisy(base + " -o " + (dir / "a.exr").string()).status, 0);
    auto exr = readExr((dir / "a.exr").string());
    ASSERT_TRUE(exr) << exr.error().message;
    EXPECT_EQ(exr->channelNames, (std::vector<std::string>{"B", "G", "R"}));

    const RunResult spectral =
        runDaisy(base + " --wavelengths 400:700:100 --spectral-exr -o " + (dir / "s.exr").string());
    ASSERT_EQ(spectral.status, 0) << spectral.output;
    std::map<std::string, std::string> attributes;
    auto spectralExr = readExr((dir / "s.exr").string(), &attributes);
    ASSERT_TRUE(spectralExr) << spectralExr.error().message;
    // Fichet et al. 2021 names, plus R, G, B for ordinary viewers; radiance B / pi = 2 / pi.
    const std::vector<std::string> names = {
        "B", "G", "R", "S0.400,000000nm", "S0.500,000000nm", "S0.600,000000nm", "S0.700,000000nm"};
    ASSERT_EQ(spectralExr->channelNames, names);
    EXPECT_EQ(attributes["spectralLayoutVersion"], "1.0");
    for (int c = 3; c < 7; ++c)
        EXPECT_NEAR(spectralExr->at(8, 6)[c], 2 / std::numbers::pi, 0.02);
}

// --subdivide 0 keeps the input triangles: the furnace's 12.
TEST(RenderCli, SubdivideZeroKeepsTheTriangles) {
    const auto dir = test::testTempDir();
    const RunResult run =
        runDaisy("render " + kFurnace + " --subdivide 0 --width 8 -o " + (dir / "a.png").string());
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("patches: 12 from 12 triangles (input triangles)"), std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("(8 x 6,"), std::string::npos) << run.output;  // 4:3 default
}

// A scene without cameras is framed automatically.
TEST(RenderCli, SceneWithoutCameraIsFramed) {
    const auto dir = test::testTempDir();
    const RunResult run = runDaisy("render " + test::assetPath("scenes/parallel_plates.gltf") +
                                   " --width 16 -o " + (dir / "a.png").string());
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("automatic framing"), std::string::npos) << run.output;
}

TEST(RenderCli, BadInputExitsTwoAndWritesNothing) {
    const auto dir = test::testTempDir();
    const std::string out = (dir / "a.png").string();
    const std::string broken = test::writeFile(dir, "broken.gltf", "{ not json");
    RunResult run = runDaisy("render " + broken + " -o " + out);
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("broken.gltf"), std::string::npos) << run.output;

    run = runDaisy("render " + kFurnace + " --camera nosuch -o " + out);
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("centre"), std::string::npos) << run.output;  // lists the cameras

    EXPECT_EQ(runDaisy("render " + kFurnace + " --spectral-exr -o " + out).status, 2);
    EXPECT_EQ(runDaisy("render " + kFurnace + " --background 1,2 -o " + out).status, 2);
    EXPECT_EQ(runDaisy("render " + kFurnace + " --exposure bright -o " + out).status, 2);
    EXPECT_EQ(runDaisy("render " + kFurnace + " -o " + (dir / "a.jpg").string()).status, 2);
    EXPECT_EQ(fileCount(dir), 1u);  // broken.gltf only
}

// An unwritable output (a directory that does not exist, a name taken by a directory) is found
// before any work (status 2, bad usage), and nothing is left behind.
TEST(RenderCli, UnwritableOutputExitsTwoWithoutPartialFile) {
    const auto dir = test::testTempDir();
    const RunResult run =
        runDaisy("render " + kFurnace + " -o " + (dir / "missing" / "a.png").string());
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("missing"), std::string::npos) << run.output;
    EXPECT_EQ(fileCount(dir), 0u);

    std::filesystem::create_directory(dir / "taken.png");
    const RunResult taken = runDaisy("render " + kFurnace + " --width 8 --subdivide 0 -o " +
                                     (dir / "taken.png").string());
    EXPECT_EQ(taken.status, 2) << taken.output;
    EXPECT_EQ(taken.output.find("view factors"), std::string::npos) << taken.output;
    EXPECT_NE(taken.output.find("taken.png"), std::string::npos) << taken.output;
    EXPECT_EQ(fileCount(dir), 1u);  // the directory, no temporary left behind
}

}  // namespace
}  // namespace daisy
