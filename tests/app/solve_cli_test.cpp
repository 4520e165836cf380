// Runs `daisy solve` (DESIGN.md section 9): the summary line, the patch table's
// E_/B_/XYZ columns, --verbose energy bookkeeping, and exit status 2 for bad
// input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "test_util.h"

namespace daisy {
namespace {

using test::runDaisy;
using test::RunResult;

std::string cornellBox() {
    return test::assetPath("scenes/cornell_box.gltf");
}

TEST(SolveCli, PrintsTheSummaryAndWritesThePatchTable) {
    const std::string csv = (test::testTempDir() / "solve_patches.csv").string();
    const RunResult run = runDaisy("solve " + cornellBox() +
                                   " --subdivide 0 --wavelengths 400:700:100 --patches-out " + csv);
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_TRUE(std::regex_search(run.output,
                                  std::regex("solve: [0-9]+ iterations, residual [0-9.e+-]+, "
                                             "[0-9.e+-]+ s")))
        << run.output;
    std::ifstream in(csv);
    std::string header, row;
    ASSERT_TRUE(std::getline(in, header));
    EXPECT_EQ(header,
              "patch,triangle,area,cx,cy,cz,nx,ny,nz,material,E_400,E_"
              "500,E_600,E_700,B_400,"
              "B_500,B_600,B_700,X,Y,Z");
    int rows = 0;
    bool someLit = false;
    while (std::getline(in, row)) {
        ++rows;
        EXPECT_EQ(row.find("nan"), std::string::npos) << row;
        // B >= E >= 0 (B = E + non-negative reflected light): check Y > 0
        // somewhere.
        const std::string y = row.substr(row.rfind(',', row.rfind(',') - 1) + 1);
        someLit = someLit || std::stod(y) > 0;
    }
    EXPECT_EQ(rows, 38);
    EXPECT_TRUE(someLit);
}

TEST(SolveCli, VerbosePrintsTheEnergyBalance) {
    const RunResult run = runDaisy("solve " + cornellBox() + " --verbose --solver jacobi");
    ASSERT_EQ(run.status, 0) << run.output;
    for (const char* line : {"emitted", "absorbed", "escaped", "converted", "balance"})
        EXPECT_NE(run.output.find(line), std::string::npos) << line << "\n" << run.output;
}

// A closed cube (OBJ, faces inward) with a black-light floor and brightener
// walls: `auto` adds the UV samples, fluorescence converts power, and the
// energy balance closes.
TEST(SolveCli, FluorescentSceneGetsUvSamplesAndConverts) {
    const auto dir = test::testTempDir();
    test::writeFile(dir, "box.mtl",
                    "newmtl lamp\nKd 0 0 0\nKe 1 1 1\nnewmtl poster\nKd 0.8 0.8 0.8\n");
    test::writeFile(dir, "box.obj",
                    "mtllib box.mtl\n"
                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                    "usemtl lamp\nf 1 2 3\nf 1 3 4\n"
                    "usemtl poster\nf 5 8 7\nf 5 7 6\nf 1 5 6\nf 1 6 2\nf 4 3 7\nf 4 7 8\n"
                    "f 1 4 8\nf 1 8 5\nf 2 6 7\nf 2 7 3\n");
    const std::string materials =
        test::writeFile(dir, "materials.json",
                        R"({"lamp": {"emission": {"preset": "blacklight", "scale": 20}},
            "poster": {"fluorescence": {"preset": "brightener"}}})");
    const RunResult run = runDaisy("solve " + (dir / "box.obj").string() + " --materials " +
                                   materials + " --subdivide 0.5 --verbose");
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("(scene has UV lights and fluorescent materials)"), std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("1 fluorescent"), std::string::npos) << run.output;
    std::smatch match;
    ASSERT_TRUE(std::regex_search(run.output, match, std::regex("converted  ([0-9.e+-]+)")));
    EXPECT_GT(std::stod(match[1]), 0);
    ASSERT_TRUE(std::regex_search(run.output, match, std::regex("/ emitted = (-?[0-9.e+-]+)")));
    EXPECT_LT(std::abs(std::stod(match[1])), 1e-3) << run.output;
}

TEST(SolveCli, IterationLimitWarnsButSucceeds) {
    const RunResult run = runDaisy("solve " + cornellBox() + " --solver jacobi --max-iterations 2");
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("not converged after 2 iterations"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("solve: 2 iterations"), std::string::npos) << run.output;
}

TEST(SolveCli, BadInputExitsTwo) {
    EXPECT_EQ(runDaisy("solve /nonexistent/scene.gltf").status, 2);
    EXPECT_EQ(runDaisy("solve " + cornellBox() + " --solver conjugate-gradient").status, 2);
    EXPECT_EQ(runDaisy("solve " + cornellBox() + " --wavelengths 700:400:10").status, 2);
}

}  // namespace
}  // namespace daisy
