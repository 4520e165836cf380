// The measured Cornell box's colours, read from the solved patch table of `daisy solve`
// (X, Y, Z of each patch's radiosity; docs/cli.md), so they do not depend on exposure or the
// image: the white back wall takes the warm colour of the measured light, and the red and green
// walls bleed their colour onto the sides of the blocks that face them.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "spectral/color.h"
#include "test_util.h"

namespace daisy {
namespace {

struct PatchRow {
    std::size_t triangle = 0;
    double area = 0;
    std::array<double, 3> centroid{}, normal{};
    std::string material;
    Xyz xyz{};
};

std::vector<PatchRow> readPatches(const std::string& path) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    std::vector<std::string> header;
    {
        std::stringstream names(line);
        std::string name;
        while (std::getline(names, name, ','))
            header.push_back(name);
    }
    const std::size_t xColumn = header.size() - 3;
    std::vector<PatchRow> rows;
    while (std::getline(in, line)) {
        std::stringstream fields(line);
        std::vector<std::string> cells;
        std::string cell;
        while (std::getline(fields, cell, ','))
            cells.push_back(cell);
        PatchRow row;
        row.triangle = std::stoul(cells[1]);
        row.area = std::stod(cells[2]);
        for (int k = 0; k < 3; ++k) {
            row.centroid[k] = std::stod(cells[3 + k]);
            row.normal[k] = std::stod(cells[6 + k]);
            row.xyz[k] = std::stod(cells[xColumn + k]);
        }
        row.material = cells[9];
        rows.push_back(row);
    }
    return rows;
}

// Area-weighted mean XYZ of the rows that pass `keep`.
template <typename Keep>
Xyz meanXyz(const std::vector<PatchRow>& rows, Keep keep) {
    Xyz sum{};
    double area = 0;
    for (const PatchRow& row : rows) {
        if (!keep(row)) continue;
        for (int k = 0; k < 3; ++k)
            sum[k] += row.area * row.xyz[k];
        area += row.area;
    }
    EXPECT_GT(area, 0);
    for (double& v : sum)
        v /= area;
    return sum;
}

// McCamy 1992 (Color Res. Appl. 17(2)): correlated colour temperature from CIE 1931 x, y,
// within a few kelvin of the exact value between 2,000 and 12,500 K.
double mccamyCct(const Xyz& xyz) {
    const double s = xyz[0] + xyz[1] + xyz[2];
    const double n = (xyz[0] / s - 0.3320) / (0.1858 - xyz[1] / s);
    return ((449 * n + 3525) * n + 6823.3) * n + 5520.33;
}

class CornellColours : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        const auto dir = std::filesystem::temp_directory_path() / "daisy_tests" / "CornellColours";
        std::filesystem::create_directories(dir);
        const std::string csv = (dir / "cornell_patches.csv").string();
        const test::RunResult run =
            test::runDaisy("solve " + test::assetPath("scenes/cornell_box.gltf") +
                           " --subdivide 0.05 -q --patches-out " + csv);
        ASSERT_EQ(run.status, 0) << run.output;
        rows_ = new std::vector<PatchRow>(readPatches(csv));
    }
    static void TearDownTestSuite() {
        delete rows_;
        rows_ = nullptr;
    }
    static std::vector<PatchRow>* rows_;
};
std::vector<PatchRow>* CornellColours::rows_ = nullptr;

// The measured light's relative spectrum rises from 0 at 400 nm to 18.4 at 700 nm
// (assets/reference/cornell_box.json), a warm light; the white paint is nearly flat, so the
// back wall must be on the warm side of D65: CCT below 6,500 K and x above D65's 0.3127. It
// must also stay near the light's own colour (the emitter patches, whose B is mostly E): within
// 0.03 in x and y, the shift the red and green walls' interreflections may add. Measured at
// --subdivide 0.05: wall (0.440, 0.423), 3,100 K; light (0.436, 0.418).
TEST_F(CornellColours, BackWallIsNeutralToWarmLikeTheLight) {
    ASSERT_NE(rows_, nullptr);
    const Xyz wall = meanXyz(*rows_, [](const PatchRow& r) {
        return r.material == "white" && r.normal[2] < -0.99 && r.centroid[2] > 0.55;
    });
    const Xyz light = meanXyz(*rows_, [](const PatchRow& r) { return r.material == "emitter"; });
    const auto chromaticity = [](const Xyz& c) {
        const double s = c[0] + c[1] + c[2];
        return std::array<double, 2>{c[0] / s, c[1] / s};
    };
    const auto w = chromaticity(wall), l = chromaticity(light);
    EXPECT_GT(w[0], 0.3127);
    EXPECT_LT(mccamyCct(wall), 6500);
    EXPECT_GT(mccamyCct(wall), 2000);
    EXPECT_NEAR(w[0], l[0], 0.03);
    EXPECT_NEAR(w[1], l[1], 0.03);
    std::printf("back wall x %.4f y %.4f CCT %.0f K; light x %.4f y %.4f\n", w[0], w[1],
                mccamyCct(wall), l[0], l[1]);
}

// Colour bleeding: the red wall is at x = 0.55 m (faces -x), the green one at x = 0 (faces +x).
// The blocks' vertical faces that look towards the red wall (normal x > 0.5) receive its red
// light, those looking towards the green wall (x < -0.5) its green light, so in linear sRGB the
// first are redder (R / G larger) than the second. Measured at --subdivide 0.05: R / G = 4.2
// against 1.4 (both above 1: the light itself is warm); the test asks for a 20% difference.
TEST_F(CornellColours, RedAndGreenWallsBleedOntoTheBlocks) {
    ASSERT_NE(rows_, nullptr);
    // The blocks are triangles 18..37 (tools/make_cornell_box.py writes them after the room).
    const auto blockSide = [](const PatchRow& r, double sign) {
        return r.triangle >= 18 && sign * r.normal[0] > 0.5;
    };
    const Rgb towardsRed =
        xyzToLinearSrgb(meanXyz(*rows_, [&](const PatchRow& r) { return blockSide(r, 1); }));
    const Rgb towardsGreen =
        xyzToLinearSrgb(meanXyz(*rows_, [&](const PatchRow& r) { return blockSide(r, -1); }));
    const double redRatio = towardsRed[0] / towardsRed[1];
    const double greenRatio = towardsGreen[0] / towardsGreen[1];
    EXPECT_GT(redRatio, 1.2 * greenRatio) << redRatio << " vs " << greenRatio;
    std::printf("block sides R/G: towards red %.3f, towards green %.3f\n", redRatio, greenRatio);
    EXPECT_GT(towardsGreen[1] / towardsGreen[0], towardsRed[1] / towardsRed[0]);
}

}  // namespace
}  // namespace daisy
