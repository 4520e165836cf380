// `daisy view` end to end: the viewer under a display (Xvfb via xvfb-run when
// DISPLAY is unset) on Mesa lavapipe (tests/CMakeLists.txt). Without a display or a Vulkan device
// the tests skip, and fail instead under DAISY_REQUIRE_VULKAN=1 (what CI sets).
#if DAISY_HAVE_VIEWER
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>
#include <utility>

#include <unistd.h>

#include "image/image_io.h"
#include "scene/gltf_builder.h"
#include "shared/viewer_types.h"
#include "spectral/color.h"
#include "test_util.h"

namespace daisy {
namespace {

using test::RunResult;

// The Cornell box at a coarse patch size: a few hundred patches, F in about a second.
const std::string kScene = test::assetPath("scenes/cornell_box.gltf") + " --subdivide 0.1";
const std::string kSize = " --camera measured --width 160 --height 120";

// Runs `daisy view ARGUMENTS` with the test's own cache, under xvfb-run when there is no display
// (with `withDisplay` false: with none at all).
RunResult runView(const std::string& arguments, bool withDisplay = true) {
    const char* display = std::getenv("DISPLAY");
    const bool haveDisplay = display && display[0] != '\0';
    // ctest runs tests in parallel: each starts its search for a free X display at its own
    // number (xvfb-run -a takes the first free one from -n on), so two rarely race for one.
    std::string prefix;
    bool usesXvfb = false;
    if (!withDisplay) {
        prefix = "env -u DISPLAY -u WAYLAND_DISPLAY ";
    } else if (!haveDisplay) {
        usesXvfb = true;
        prefix = "xvfb-run -a -n " + std::to_string(100 + getpid() % 800) +
            " -s '-screen 0 1600x1200x24' ";
    }
    const std::string command = "XDG_CACHE_HOME='" + test::testCacheHome().string() + "' " +
        prefix + DAISY_EXE_PATH + " view " + arguments + " 2>&1";
    for (int attempt = 0;; ++attempt) {
        RunResult result;
        FILE* pipe = popen(command.c_str(), "r");
        if (!pipe) return result;
        char buffer[4096];
        std::size_t count;
        while ((count = fread(buffer, 1, sizeof buffer, pipe)) > 0)
            result.output.append(buffer, count);
        const int raw = pclose(pipe);
        result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
        // xvfb-run itself can fail on a loaded machine with tests starting servers in parallel:
        // its clean-up loses a race for its temporary folder (exit 5 in place of daisy's
        // status), or its server is not up when daisy connects. Those runs say nothing about
        // daisy: run again, at most twice.
        const bool xvfbCleanUp = result.status == 5 &&
            result.output.find("problem while cleaning up temporary directory") !=
                std::string::npos;
        const bool xvfbNotUp =
            usesXvfb && result.output.find("cannot open a window (no display") != std::string::npos;
        if ((!xvfbCleanUp && !xvfbNotUp) || attempt >= 2) return result;
    }
}

// Why the viewer could not run here (no display, no Vulkan device that presents), or "".
std::string unavailable(const RunResult& run) {
    for (const char* reason : {"cannot open a window", "no Vulkan", "GLFW finds no Vulkan",
                               "xvfb-run: not found", "command not found"}) {
        if (run.output.find(reason) != std::string::npos) return run.output;
    }
    return "";
}

#define DAISY_VIEW_OR_SKIP(run)                                              \
    do {                                                                     \
        if (const std::string why = unavailable(run); !why.empty()) {        \
            DAISY_SKIP_WITHOUT_VULKAN("daisy view cannot run here: " + why); \
        }                                                                    \
    } while (0)

double meanDeltaE(const Image& a, const Image& b) {
    double sum = 0;
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            const auto lab = [](const float* p) {
                return srgb8ToLab({uint8_t(p[0]), uint8_t(p[1]), uint8_t(p[2])});
            };
            sum += deltaE2000(lab(a.at(x, y)), lab(b.at(x, y)));
        }
    }
    return sum / (double(a.width) * a.height);
}

// The share of pixels whose worst channel differs by more than `limit` of 255.
double farPixels(const Image& a, const Image& b, float limit) {
    int far = 0;
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            float worst = 0;
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::abs(a.at(x, y)[c] - b.at(x, y)[c]));
            far += worst > limit ? 1 : 0;
        }
    }
    return double(far) / (double(a.width) * a.height);
}

// The viewer's screenshot (with `viewOptions` too) and `daisy render --gather none --edge-spp 0`
// of `arguments` (the scene and size, as both take them), read back, of one size. A failure or
// skip ends the caller's test through HasFatalFailure / IsSkipped.
struct ViewAndRender {
    RunResult viewed;
    Image view, render;
};
void viewAndRender(const std::string& arguments, const std::string& viewOptions,
                   ViewAndRender& out) {
    const auto dir = test::testTempDir();
    const std::string viewPng = (dir / "view.png").string();
    const std::string renderPng = (dir / "render.png").string();
    const RunResult rendered =
        test::runDaisy("render " + arguments + " --gather none --edge-spp 0 -o " + renderPng);
    ASSERT_EQ(rendered.status, 0) << rendered.output;
    out.viewed = runView(arguments + " --frames 3 " + viewOptions + " --screenshot " + viewPng);
    DAISY_VIEW_OR_SKIP(out.viewed);
    ASSERT_EQ(out.viewed.status, 0) << out.viewed.output;
    auto view = readPng(viewPng);
    auto render = readPng(renderPng);
    ASSERT_TRUE(view) << view.error().message;
    ASSERT_TRUE(render) << render.error().message;
    ASSERT_EQ(view->width, render->width);
    ASSERT_EQ(view->height, render->height);
    out.view = std::move(*view);
    out.render = std::move(*render);
}

TEST(ViewCli, ScreenshotMatchesRenderOfTheSameCamera) {
    const auto dir = test::testTempDir();
    const std::string viewPng = (dir / "view.png").string();
    const std::string renderPng = (dir / "render.png").string();
    // The viewer's image: the smooth radiance at one sample per pixel (no edge supersampling).
    const RunResult rendered =
        test::runDaisy("render " + kScene + kSize + " --gather none --edge-spp 0 -o " + renderPng);
    ASSERT_EQ(rendered.status, 0) << rendered.output;
    const RunResult viewed = runView(kScene + kSize + " --frames 3 --screenshot " + viewPng);
    DAISY_VIEW_OR_SKIP(viewed);
    ASSERT_EQ(viewed.status, 0) << viewed.output;
    EXPECT_NE(viewed.output.find("from the cache"), std::string::npos) << viewed.output;
    auto view = readPng(viewPng);
    auto render = readPng(renderPng);
    ASSERT_TRUE(view) << view.error().message;
    ASSERT_TRUE(render) << render.error().message;
    ASSERT_EQ(view->width, 160);
    ASSERT_EQ(view->height, 120);
    ASSERT_EQ(render->width, 160);
    ASSERT_EQ(render->height, 120);
    // The same smooth vertex radiance and exposure, rasterised instead of ray-cast: pixels differ
    // only where an edge crosses a pixel centre differently. Mean CIEDE2000 under 1 is below
    // what an observer notices side by side (Sharma et al. 2005).
    const double deltaE = meanDeltaE(*view, *render);
    EXPECT_LT(deltaE, 1.0);
    double mean = 0;
    for (float v : view->pixels)
        mean += v;
    EXPECT_GT(mean / double(view->pixels.size()), 20.0);  // a lit picture, not a black frame
    std::printf("mean CIEDE2000 view vs render: %.4f\n", deltaE);
}

// Blender writes doubleSided on every material, so every wall has a back patch on the same
// triangle (PatchMesh::backPatch). The viewer must show the face turned to the camera, as the
// renderer does, and not let the coincident pair z-fight: without that, 0.12% of this picture's
// pixels differ from the render by more than 40 of 255 (dark specks on the walls); with it,
// 0.04% do (silhouette edges only).
TEST(ViewCli, DoubleSidedWallsMatchTheRenderWithoutZFighting) {
    ViewAndRender run;
    viewAndRender(test::testDataPath("blender/cornell.gltf") + " --width 320 --height 320", "",
                  run);
    if (HasFatalFailure() || IsSkipped()) return;
    EXPECT_LT(meanDeltaE(run.view, run.render), 1.0);
    EXPECT_LT(farPixels(run.view, run.render, 40), 0.0008);
}

// A one-sided grey square lit on its front by an emitting square, and a camera behind it: the
// back of a one-sided surface neither emits nor reflects, so the viewer shows it black, as
// daisy render does (the middle of both pictures, all square), though its front is lit.
TEST(ViewCli, TheBackOfAOneSidedSurfaceIsBlackAsInTheRender) {
    test::GltfBuilder gltf;
    // Both squares face +z's opposite ends: the grey one at z = 0 faces +z (the emitter at
    // z = 1 faces -z, towards it); the camera at z = -3 looks along +z at the grey one's back.
    const int grey = gltf.addPositions({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}});
    const int light = gltf.addPositions({{-1, -1, 1}, {-1, 1, 1}, {1, 1, 1}, {1, -1, 1}});
    const int quad = gltf.addIndices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
    gltf.doc["materials"] = {
        {{"name", "grey"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.7, 0.7, 0.7, 1}}}}},
        {{"name", "light"},
         {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}},
         {"emissiveFactor", {1, 1, 1}}}};
    const int mesh =
        gltf.addMesh({{{"attributes", {{"POSITION", grey}}}, {"indices", quad}, {"material", 0}},
                      {{"attributes", {{"POSITION", light}}}, {"indices", quad}, {"material", 1}}});
    // glTF cameras look along their local -z: a half turn about y looks along +z.
    gltf.doc["cameras"] = {
        {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.05}}}}};
    gltf.setScene(
        {gltf.addNode({{"mesh", mesh}}),
         gltf.addNode({{"camera", 0}, {"translation", {0, 0, -3}}, {"rotation", {0, 1, 0, 0}}})});
    // Beside the test's own folder, which viewAndRender empties.
    const auto folder = test::testTempDir().parent_path() / "ViewCli.OneSidedBackScene";
    std::filesystem::create_directories(folder);
    const std::string scene = gltf.writeGltf(folder, "back.gltf");
    ViewAndRender run;
    viewAndRender(scene + " --width 64 --height 48 --subdivide 0.5", "", run);
    if (HasFatalFailure() || IsSkipped()) return;
    for (const Image* image : {&run.view, &run.render}) {
        for (int y = 18; y < 30; ++y) {
            for (int x = 26; x < 38; ++x) {
                for (int c = 0; c < 3; ++c)
                    EXPECT_EQ(image->at(x, y)[c], 0.0f)
                        << (image == &run.view ? "view " : "render ") << x << " " << y;
            }
        }
    }
}

// The Blender room's floor is a bilinear checker texture: `daisy render` multiplies the smooth
// radiance by texel / patch mean (image/texture_detail.h), and the viewer does the same in its
// fragment shader (viewer/detail_vertices.h), so the checker is in both pictures. Without it the
// viewer showed the patch means' smooth floor: mean CIEDE2000 4.4 against the render and 13% of
// pixels more than 40 of 255 off; with it 0.25 and none (the auto exposure, measured with the
// detail as the render's, agrees too: -10.4 EV).
TEST(ViewCli, TextureDetailMatchesTheRender) {
    ViewAndRender run;
    viewAndRender(
        test::testDataPath("blender/room.gltf") + " --subdivide 1 --width 192 --height 108",
        "--verbose", run);
    if (HasFatalFailure() || IsSkipped()) return;
    EXPECT_NE(run.viewed.output.find("view: texture detail: 1 textures"), std::string::npos)
        << run.viewed.output;
    const double deltaE = meanDeltaE(run.view, run.render);
    const double far = farPixels(run.view, run.render, 40);
    std::printf("textured room: mean CIEDE2000 %.4f, %.4f%% of pixels > 40 off\n", deltaE,
                100 * far);
    EXPECT_LT(deltaE, 1.0);
    EXPECT_LT(far, 0.005);
}

TEST(ViewCli, EditedReflectanceTurnsTheRedWallGreen) {
    const auto dir = test::testTempDir();
    const std::string before = (dir / "before.png").string();
    const std::string after = (dir / "after.png").string();
    const RunResult plain = runView(kScene + kSize + " --frames 2 --screenshot " + before);
    DAISY_VIEW_OR_SKIP(plain);
    ASSERT_EQ(plain.status, 0) << plain.output;
    const RunResult edited = runView(kScene + kSize + " --frames 2 --screenshot " + after +
                                     " --edit 'red.reflectance=rgb(0,1,0)'");
    ASSERT_EQ(edited.status, 0) << edited.output;
    EXPECT_NE(edited.output.find("view: edit -> first updated frame"), std::string::npos)
        << edited.output;
    auto a = readPng(before);
    auto b = readPng(after);
    ASSERT_TRUE(a && b);
    // The red wall's pixels before the edit: red well above green and blue. Compared in linear
    // light (the IEC 61966-2-1 curve undone).
    const auto linear = [](float encoded) {
        const double c = encoded / 255.0;
        return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    };
    double redBefore = 0, greenBefore = 0, redAfter = 0, greenAfter = 0;
    int wall = 0;
    for (int y = 0; y < a->height; ++y) {
        for (int x = 0; x < a->width; ++x) {
            const float* p = a->at(x, y);
            if (!(p[0] > 2 * p[1] + 10 && p[0] > 2 * p[2] + 10)) continue;
            ++wall;
            redBefore += linear(p[0]);
            greenBefore += linear(p[1]);
            redAfter += linear(b->at(x, y)[0]);
            greenAfter += linear(b->at(x, y)[1]);
        }
    }
    ASSERT_GT(wall, 500) << "the red wall fills about a sixth of the picture";
    // Before, the wall reflects several times more red than green; after the edit to
    // rgb(0, 1, 0) (upsampled to a smooth spectrum that keeps a little red, lit by the white
    // walls' light) it is the other way round.
    EXPECT_GT(redBefore, 4 * greenBefore);
    EXPECT_GT(greenAfter, 3 * redAfter) << redAfter / wall << " " << greenAfter / wall;
}

// View, edit, save, render: `daisy render --materials` of the saved file shows what the viewer
// showed after the edits.
TEST(ViewCli, SavedMaterialsRenderAsTheViewerShowedThem) {
    const auto dir = test::testTempDir();
    const std::string viewPng = (dir / "view.png").string();
    const std::string renderPng = (dir / "render.png").string();
    const std::string saved = (dir / "edited.json").string();
    const RunResult viewed =
        runView(kScene + kSize +
                " --frames 2 --edit 'white.reflectance=rgb(0.2,0.6,0.9)' --edit "
                "'red.fluorescence={\"preset\": \"fluorescein\"}' --save-materials " +
                saved + " --screenshot " + viewPng);
    DAISY_VIEW_OR_SKIP(viewed);
    ASSERT_EQ(viewed.status, 0) << viewed.output;
    const RunResult rendered = test::runDaisy("render " + kScene + kSize + " --materials " + saved +
                                              " --gather none --edge-spp 0 -o " + renderPng);
    ASSERT_EQ(rendered.status, 0) << rendered.output;
    auto view = readPng(viewPng);
    auto render = readPng(renderPng);
    ASSERT_TRUE(view) << view.error().message;
    ASSERT_TRUE(render) << render.error().message;
    EXPECT_LT(meanDeltaE(*view, *render), 1.0);
    // And the edit shows: the back wall (right of the tall block) turned from white to
    // rgb(0.2, 0.6, 0.9): under the warm light, green well over red (white showed red >= green).
    const float* wall = view->at(110, 40);
    EXPECT_GT(wall[1], wall[0] + 20) << wall[0] << " " << wall[1] << " " << wall[2];
}

TEST(ViewCli, ResizingAndMinimisingDoNotCrash) {
    const auto dir = test::testTempDir();
    const std::string png = (dir / "resized.png").string();
    const RunResult run =
        runView(kScene + kSize + " --frames 14 --exercise-window --panel --screenshot " + png);
    DAISY_VIEW_OR_SKIP(run);
    ASSERT_EQ(run.status, 0) << run.output;
    auto image = readPng(png);
    ASSERT_TRUE(image) << image.error().message;
    // The window came back to the size asked for after being shrunk, minimised and enlarged.
    EXPECT_EQ(image->width, 160);
    EXPECT_EQ(image->height, 120);
}

TEST(ViewCli, FalseColourPutsTheLightAtTheTopOfTheRamp) {
    const auto dir = test::testTempDir();
    const std::string png = (dir / "luminance.png").string();
    const RunResult run =
        runView(kScene + kSize + " --frames 2 --display luminance --screenshot " + png);
    DAISY_VIEW_OR_SKIP(run);
    ASSERT_EQ(run.status, 0) << run.output;
    auto image = readPng(png);
    ASSERT_TRUE(image) << image.error().message;
    // The automatic range ends at the largest luminance, the light's (emitters are not smoothed
    // across the material boundary): its pixels are the ramp's last stop, and only they are.
    const shared::vec3 top = shared::falseColour(1.0f);
    int lit = 0, lowest = 0;
    for (int y = 0; y < image->height; ++y) {
        for (int x = 0; x < image->width; ++x) {
            const float* p = image->at(x, y);
            if (std::abs(p[0] - 255 * top.x) <= 2 && std::abs(p[1] - 255 * top.y) <= 2 &&
                std::abs(p[2] - 255 * top.z) <= 2) {
                ++lit;
                lowest = std::max(lowest, y);
            }
        }
    }
    EXPECT_GE(lit, 20);
    EXPECT_LT(lowest, image->height / 5) << "the light is in the ceiling";
    const RunResult bad = runView(kScene + " --display infrared");
    EXPECT_EQ(bad.status, 2) << bad.output;
    EXPECT_NE(bad.output.find("'infrared' is not one of"), std::string::npos) << bad.output;
}

TEST(ViewCli, PickNamesThePatchUnderThePixel) {
    // The measured camera sees the red wall on the left, the green one on the right and the
    // light in the ceiling's middle (assets/scenes/cornell_box.gltf, tools/make_cornell_box.py).
    // The panel is docked on the left half of the 320-pixel window: the picture is the 160 x 120
    // to its right, so window pixel 190 is the picture's 30.
    for (const auto& [pixel, material] :
         {std::pair<std::string, std::string>{"190,60", "red"}, {"290,60", "green"}}) {
        const RunResult run =
            runView(kScene +
                    " --camera measured --width 320 --height 120 --frames 1 --panel "
                    "--pick " +
                    pixel);
        DAISY_VIEW_OR_SKIP(run);
        ASSERT_EQ(run.status, 0) << run.output;
        EXPECT_NE(run.output.find("(material '" + material + "')"), std::string::npos)
            << pixel << "\n"
            << run.output;
    }
}

TEST(ViewCli, RefusedEditSaysWhyAndExitsTwo) {
    // Absorption 1 at every visible wavelength on top of the white walls' reflectance: rho + a
    // exceeds 1 (DESIGN.md section 5), so the session refuses the edit.
    const RunResult run = runView(
        kScene + kSize +
        " --frames 2 --edit 'white.fluorescence={\"absorption\": {\"gaussian\": {\"peak\": 550, "
        "\"fwhm\": 2000}}, \"emission\": {\"gaussian\": {\"peak\": 600, \"fwhm\": 40}}, "
        "\"quantumYield\": 0.5}'");
    DAISY_VIEW_OR_SKIP(run);
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("edit refused"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("white"), std::string::npos) << run.output;
}

// The window opens before F is made: the first frame (logged with what it shows) is drawn while
// the view factors are built, before the build's closing line; the converged frame comes after.
// The Cornell box at 0.05: a few thousand patches, F in a second or more.
TEST(ViewCli, FirstFrameComesWhileTheViewFactorsAreMade) {
    const std::string scene = test::assetPath("scenes/cornell_box.gltf") + " --subdivide 0.05";
    const RunResult run = runView(scene + kSize + " --frames 2 --backend cpu");
    DAISY_VIEW_OR_SKIP(run);
    ASSERT_EQ(run.status, 0) << run.output;
    const std::size_t first = run.output.find("view: first frame ");
    const std::size_t built = run.output.find(" non-zeros in ");  // "view factors: N non-zeros in"
    const std::size_t converged = run.output.find("view: first converged frame ");
    ASSERT_NE(first, std::string::npos) << run.output;
    ASSERT_NE(built, std::string::npos) << run.output;
    ASSERT_NE(converged, std::string::npos) << run.output;
    EXPECT_LT(first, built) << run.output;
    EXPECT_LT(built, converged) << run.output;
    const std::string line = run.output.substr(first, run.output.find('\n', first) - first);
    // The emission, or already the emitters' direct light (shadow rays, no F).
    EXPECT_NE(line.find(" while the view factors are made"), std::string::npos) << line;
}

// A warm open: the second view of the same scene and materials takes the converged solution from
// the disk cache (no solve) and shows the same picture.
TEST(ViewCli, AWarmOpenShowsTheCachedSolutionWithoutSolving) {
    const auto dir = test::testTempDir();
    const std::string coldPng = (dir / "cold.png").string();
    const std::string warmPng = (dir / "warm.png").string();
    const RunResult cold = runView(kScene + kSize + " --frames 2 --screenshot " + coldPng);
    DAISY_VIEW_OR_SKIP(cold);
    ASSERT_EQ(cold.status, 0) << cold.output;
    const std::regex solved("solve: [0-9]+ iterations");
    EXPECT_TRUE(std::regex_search(cold.output, solved)) << cold.output;
    const RunResult warm = runView(kScene + kSize + " --frames 2 --screenshot " + warmPng);
    ASSERT_EQ(warm.status, 0) << warm.output;
    EXPECT_NE(warm.output.find("solve: the converged solution from the cache"), std::string::npos)
        << warm.output;
    EXPECT_FALSE(std::regex_search(warm.output, solved)) << warm.output;
    EXPECT_NE(warm.output.find("view: first converged frame"), std::string::npos) << warm.output;
    auto a = readPng(coldPng);
    auto b = readPng(warmPng);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->pixels, b->pixels);
}

TEST(ViewCli, NoDisplayFailsBeforeTheViewFactors) {
    const RunResult run = runView(kScene + " --frames 1", false);
    EXPECT_EQ(run.status, 1) << run.output;
    EXPECT_NE(run.output.find("cannot open a window (no display"), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("view factors"), std::string::npos) << run.output;
}

TEST(ViewCli, BadOptionsFailBeforeTheViewFactors) {
    for (const std::string& arguments :
         {kScene + " --camera nosuch --frames 1", kScene + " --edit 'floor.reflectance=rgb(0,1,0)'",
          kScene + " --edit 'red.reflectance=rgb(3,0,0)'", kScene + " --device 99 --frames 1",
          kScene + " --frames 1 --screenshot /proc/no/such.png"}) {
        const RunResult run = runView(arguments);
        EXPECT_EQ(run.status, 2) << arguments << "\n" << run.output;
        EXPECT_EQ(run.output.find("view factors"), std::string::npos) << run.output;
    }
}

// Without the disk cache the backend is chosen (and Vulkan probed, headless) while the window
// is open; the probe's instance used to replace volk's table of instance functions, so the
// window's vkDestroySurfaceKHR was null at exit (status 139).
TEST(ViewCli, OpeningWithoutTheCacheExitsCleanly) {
    const RunResult run = runView(kScene + kSize + " --no-cache --frames 3");
    EXPECT_EQ(run.status, 0) << run.output;
}

}  // namespace
}  // namespace daisy
#endif
