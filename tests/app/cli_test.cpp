// Runs the `daisy` executable and checks the command-line contract of DESIGN.md section 9:
// exit status 0 done, 2 bad usage or input with a one-line message naming the problem.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>

#include "test_util.h"

namespace daisy {
namespace {

using test::runDaisy;
using test::RunResult;

std::string cornellBox() {
    return test::assetPath("scenes/cornell_box.gltf");
}

int lineCount(const std::string& text) {
    int lines = 0;
    for (char c : text)
        lines += c == '\n';
    return lines;
}

TEST(Cli, InfoDescribesTheCornellBox) {
    const RunResult run = runDaisy("info " + cornellBox());
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("triangles      38"), std::string::npos) << run.output;
    // info shows the patches render solves: the automatic size.
    EXPECT_NE(run.output.find(", the automatic size; bound"), std::string::npos) << run.output;
    const RunResult unsubdivided = runDaisy("info " + cornellBox() + " --subdivide 0");
    EXPECT_NE(unsubdivided.output.find("patches        38 (no subdivision)"), std::string::npos)
        << unsubdivided.output;
    EXPECT_NE(run.output.find("emitter (emissive)"), std::string::npos);
    EXPECT_NE(run.output.find("cameras        1: measured"), std::string::npos);
    EXPECT_NE(run.output.find("as CSR"), std::string::npos);
}

TEST(Cli, InfoWithSubdivisionCountsMorePatches) {
    const RunResult run = runDaisy("info " + cornellBox() + " --subdivide 0.1");
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("(subdivided to edges <= 0.1"), std::string::npos) << run.output;
}

// A subdivision whose patches alone would not fit is refused before anything is allocated.
TEST(Cli, InfoRefusesSubdivisionOverMaxMemory) {
    const RunResult run = runDaisy("info " + cornellBox() + " --subdivide 0.0001 --max-memory 1G");
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_EQ(lineCount(run.output), 1) << run.output;
    EXPECT_NE(run.output.find("use a larger --subdivide"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("--max-memory 1.00 GiB"), std::string::npos) << run.output;
}

TEST(Cli, HelpAndVersionExitZero) {
    EXPECT_EQ(runDaisy("--help").status, 0);
    EXPECT_EQ(runDaisy("render --help").status, 0);
    const RunResult version = runDaisy("--version");
    EXPECT_EQ(version.status, 0);
    EXPECT_NE(version.output.find("daisy 0.1.0"), std::string::npos);
}

// Each bad invocation gets exit status 2 and one line that names what is wrong.
TEST(Cli, BadUsageIsOneLineAndExitTwo) {
    const std::string scene = cornellBox();
    const std::pair<std::string, std::string> cases[] = {
        {"", "subcommand"},
        {"paint " + scene, "paint"},
        {"info", "SCENE"},
        {"info /nonexistent.gltf", "/nonexistent.gltf"},
        {"info " + scene + " --frobnicate", "--frobnicate"},
        {"info " + scene + " --method fancy", "fancy"},
        {"info " + scene + " --backend metal", "metal"},
        {"info " + scene + " --rays -1", "--rays"},
        {"info " + scene + " --quadrature 9", "--quadrature"},
        {"info " + scene + " --subdivide -0.5", "--subdivide"},
        {"info " + scene + " --subdivide abc", "--subdivide"},
        {"info " + scene + " --wavelengths 700:400:10", "700:400:10"},
        {"info " + scene + " --wavelengths rgb", "rgb"},
        {"info " + scene + " --solver newton", "newton"},
        {"info " + scene + " --tolerance 0", "--tolerance"},
        {"info " + scene + " --max-iterations 0", "--max-iterations"},
        {"info " + scene + " --max-memory lots", "lots"},
        {"info " + scene + " --quiet --verbose", "--verbose"},
        {"info " + scene + " --mtl-convention wavefront", "wavefront"},
        {"info " + scene + " --materials /nonexistent.json", "/nonexistent.json"},
        {"render " + scene + " -o out.jpg", ".png"},
        {"render " + scene + " --width 0", "--width"},
        {"render " + scene + " --exposure bright", "bright"},
        {"formfactors " + scene, "--output"},
        {"validate " + scene + " --backend cpu", "vulkan or cuda"},
    };
    for (const auto& [arguments, mention] : cases) {
        const RunResult run = runDaisy(arguments);
        EXPECT_EQ(run.status, 2) << arguments << "\n" << run.output;
        EXPECT_EQ(lineCount(run.output), 1) << arguments << "\n" << run.output;
        EXPECT_NE(run.output.find(mention), std::string::npos) << arguments << "\n" << run.output;
    }
}

TEST(Cli, BadSceneContentIsExitTwoNamingTheFile) {
    const auto dir = test::testTempDir();
    const std::string bad = test::writeFile(dir, "broken.gltf", "{ \"asset\": { \"version\": ");
    const RunResult run = runDaisy("info " + bad);
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("broken.gltf"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace daisy
