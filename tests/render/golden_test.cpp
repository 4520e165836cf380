// Golden images: small renders of each demo scene through the `daisy render` command
// line, compared pixel by pixel with the committed references in tests/golden/ in CIEDE2000
// (spectral/color.h, sRGB white). Tolerance: mean Delta E00 <= 1 (about one just-noticeable
// difference, Sharma et al. 2005) and 99th percentile <= 3, which leaves room for the pixels on
// silhouettes, where a different compiler or ray-caster ISA may pick the other surface of an edge,
// while any change to the view factors, the solve, the shading or exposure that a viewer could
// see fails. Each render uses fixed settings (size, patch size, method, exposure) so that it
// runs in a few seconds and does not depend on the automatic choices.
//
// To regenerate the references after an intended change, run
//   DAISY_UPDATE_GOLDEN=1 build/tests/daisy_tests --gtest_filter='Golden*'
// and look at every image in tests/golden/ before committing it (tests/golden/README.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "image/image_io.h"
#include "spectral/color.h"
#include "test_util.h"

namespace daisy {
namespace {

struct GoldenCase {
    const char* name;  // tests/golden/<name>.png
    const char* scene;  // under assets/scenes/
    const char* arguments;
};

// 96 x 72 (the Cornell box's square camera: 72 x 72), 4 samples per pixel, fixed EV from the
// automatic exposure of the default render. Patch sizes keep each solve under a few seconds.
const GoldenCase kCases[] = {
    {"cornell_box", "cornell_box.gltf",
     "--width 72 --height 72 --spp 4 --subdivide 0.06 --exposure 3"},
    {"blacklight_box", "blacklight_box.gltf",
     "--width 96 --height 72 --spp 4 --subdivide 0 --method riemann --rays 4 --exposure 6"},
    {"colored_lights", "colored_lights.gltf",
     "--width 96 --height 72 --spp 4 --subdivide 0.3 --exposure -1.5"},
    {"furnace_box", "furnace_box.gltf", "--width 48 --height 36 --subdivide 0 --exposure -1"},
};

std::string goldenPath(const std::string& name) {
    return std::string(DAISY_GOLDEN_DIR) + "/" + name + ".png";
}

class Golden : public ::testing::TestWithParam<GoldenCase> {};

TEST_P(Golden, MatchesTheReference) {
    const GoldenCase& golden = GetParam();
    const std::string out = (test::testTempDir() / (std::string(golden.name) + ".png")).string();
    const test::RunResult run =
        test::runDaisy(std::string("render ") + test::assetPath("scenes/") + golden.scene + " " +
                       golden.arguments + " -q -o " + out);
    ASSERT_EQ(run.status, 0) << run.output;
    if (std::getenv("DAISY_UPDATE_GOLDEN")) {
        std::filesystem::copy_file(out, goldenPath(golden.name),
                                   std::filesystem::copy_options::overwrite_existing);
        GTEST_SKIP() << "updated " << goldenPath(golden.name);
    }
    auto reference = readPng(goldenPath(golden.name));
    ASSERT_TRUE(reference) << reference.error().message;
    auto rendered = readPng(out);
    ASSERT_TRUE(rendered) << rendered.error().message;
    ASSERT_EQ(rendered->width, reference->width);
    ASSERT_EQ(rendered->height, reference->height);

    std::vector<double> differences;
    double sum = 0;
    const auto byte = [](float v) { return static_cast<uint8_t>(v); };
    for (int y = 0; y < reference->height; ++y) {
        for (int x = 0; x < reference->width; ++x) {
            const float* a = reference->at(x, y);
            const float* b = rendered->at(x, y);
            const double d = deltaE2000(srgb8ToLab({byte(a[0]), byte(a[1]), byte(a[2])}),
                                        srgb8ToLab({byte(b[0]), byte(b[1]), byte(b[2])}));
            differences.push_back(d);
            sum += d;
        }
    }
    std::sort(differences.begin(), differences.end());
    const double mean = sum / double(differences.size());
    const double p99 = differences[std::size_t(0.99 * double(differences.size() - 1))];
    EXPECT_LE(mean, 1.0) << "rendered " << out << " against " << goldenPath(golden.name);
    EXPECT_LE(p99, 3.0) << "rendered " << out << " against " << goldenPath(golden.name);
}

INSTANTIATE_TEST_SUITE_P(DemoScenes, Golden, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<GoldenCase>& param) {
                             return std::string(param.param.name);
                         });

}  // namespace
}  // namespace daisy
