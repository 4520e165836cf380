// `daisy formfactors` end to end (DESIGN.md section 9): the files it writes, the memory refusal
// and the backend registry, through the real executable.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "radiosity/matrix_market.h"
#include "test_util.h"

namespace daisy {
namespace {

using test::runDaisy;
using test::RunResult;

const std::string kCornellBox = test::assetPath("scenes/cornell_box.gltf");

std::string readText(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

TEST(FormFactorsCli, WritesTheMatrixAndThePatchTable) {
    const auto dir = test::testTempDir();
    const auto matrixPath = (dir / "F.mtx").string();
    const auto patchesPath = (dir / "patches.csv").string();
    const RunResult run = runDaisy("formfactors " + kCornellBox + " -o " + matrixPath +
                                   " --patches-out " + patchesPath + " --verbose");
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("facing away"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("clear shafts"), std::string::npos) << run.output;

    auto matrix = readMatrixMarket(matrixPath);
    ASSERT_TRUE(matrix.ok()) << matrix.error().message;
    EXPECT_EQ(matrix->size, 38u);  // the Cornell box's 38 triangles
    EXPECT_GT(matrix->nonzeroCount(), 0u);
    // An open box: every row sums to at most 1 (the rest leaves through the opening).
    for (double sum : rowSums(*matrix))
        EXPECT_LE(sum, 1.0 + 1e-4);
    EXPECT_EQ(readText(matrixPath).rfind("%%MatrixMarket matrix coordinate real general\n", 0), 0u);

    const std::string csv = readText(patchesPath);
    EXPECT_EQ(csv.rfind("patch,triangle,area,cx,cy,cz,nx,ny,nz,material\n0,0,", 0), 0u) << csv;
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 39);
}

// Refused before any work, exit status 2, one line naming the limit; no file is left behind.
TEST(FormFactorsCli, RefusesOverMaxMemory) {
    const auto dir = test::testTempDir();
    const auto matrixPath = dir / "F.mtx";
    const RunResult run = runDaisy("formfactors " + kCornellBox + " --subdivide 0.01 -o " +
                                   matrixPath.string() + " --max-memory 1M --quiet");
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
    EXPECT_NE(run.output.find("--max-memory 1.00 MiB"), std::string::npos) << run.output;
    EXPECT_FALSE(std::filesystem::exists(matrixPath));
}

// --backend cuda where it cannot run (no nvcc at build time; no driver or device; --device 99):
// exit status 2, one line naming the backend and why, and no output file.
TEST(FormFactorsCli, CudaWithoutADeviceIsOneLineExitTwo) {
    const auto dir = test::testTempDir();
    const auto matrixPath = dir / "F.mtx";
    const RunResult run = runDaisy("formfactors " + kCornellBox + " -o " + matrixPath.string() +
                                   " --quiet --backend cuda --device 99");
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
    EXPECT_NE(run.output.find("--backend cuda: "), std::string::npos) << run.output;
#if DAISY_HAVE_CUDA
    EXPECT_TRUE(run.output.find("no CUDA device") != std::string::npos ||
                run.output.find("--device 99: there is no CUDA device 99") != std::string::npos)
        << run.output;
#else
    EXPECT_NE(run.output.find("backend 'cuda' is not built into this binary"), std::string::npos)
        << run.output;
#endif
    EXPECT_FALSE(std::filesystem::exists(matrixPath));
}

// An unwritable output is bad usage (exit 2) found before any work, naming the path, with no
// partial file.
TEST(FormFactorsCli, UnwritableOutputFailsCleanly) {
    const auto dir = test::testTempDir();
    const std::string path = (dir / "missing_dir" / "F.mtx").string();
    const RunResult run = runDaisy("formfactors " + kCornellBox + " -o " + path + " --quiet");
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_EQ(run.output.find("view factors"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find(path), std::string::npos) << run.output;
    EXPECT_TRUE(std::filesystem::is_empty(dir));
}

// The cost model's choice is in --verbose: its prices and what it culled or traced. The prices
// are fixed and the work counted, so its choices, and the line, are the same for any thread
// count (and load), and so is F, byte for byte.
TEST(FormFactorsCli, VerboseLogsTheCostModelsChoice) {
    const auto dir = test::testTempDir();
    const std::string scene = test::assetPath("scenes/formfactor_family/blacklight_small.gltf");
    std::string lines[2];
    std::string matrices[2];
    for (int threads : {1, 2}) {
        const std::string out = (dir / (threads == 1 ? "F1.mtx" : "F2.mtx")).string();
        const RunResult run =
            runDaisy("formfactors " + scene + " -o " + out + " --verbose --no-cache --threads " +
                     (threads == 1 ? "1" : "2"));
        ASSERT_EQ(run.status, 0) << run.output;
        const std::size_t at = run.output.find("  cost model (fixed prices");
        ASSERT_NE(at, std::string::npos) << run.output;
        const std::string line = run.output.substr(at, run.output.find('\n', at) - at);
        EXPECT_NE(line.find(" cluster pairs, traced "), std::string::npos) << line;
        EXPECT_NE(line.find(" refinements; culling priced at "), std::string::npos) << line;
        lines[threads - 1] = line;
        matrices[threads - 1] = test::readBytes(out);
    }
    EXPECT_EQ(lines[0], lines[1]);
    EXPECT_FALSE(matrices[0].empty());
    EXPECT_TRUE(matrices[0] == matrices[1]) << "F differs between --threads 1 and 2";
}

// F does not depend on the instruction set: the cpu backend's lanes (far field, samples) round
// as the scalar kernel does and every segment is decided by the shared watertight test, so the
// same command with DAISY_ISA=sse2, avx2 and the processor's widest writes the same bytes (on
// the cluttered scene, whose boxes on the floor once gave 838 to 1,324 entries that differed
// from the reference, a different count on each ISA: Embree's coherent packets).
TEST(FormFactorsCli, SameMatrixOnEveryInstructionSet) {
    const auto dir = test::testTempDir();
    const std::string scene = test::assetPath("scenes/formfactor_family/cluttered_small.gltf");
    std::string first;
    for (const char* isa : {"", "avx2", "sse2"}) {
        const std::string out = (dir / (std::string("F_") + isa + ".mtx")).string();
        const std::string command = std::string("DAISY_ISA=") + isa + " " + DAISY_EXE_PATH +
            " formfactors " + scene + " --backend cpu --no-cache --quiet -o " + out;
        ASSERT_EQ(std::system(command.c_str()), 0) << command;
        const std::string bytes = readText(out);
        ASSERT_GT(bytes.size(), 1000u) << out;
        if (first.empty()) {
            first = bytes;
        } else {
            EXPECT_TRUE(bytes == first) << "DAISY_ISA=" << isa << " wrote another matrix";
        }
    }
}

}  // namespace
}  // namespace daisy
