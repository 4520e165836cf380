// SIGINT / SIGTERM (core/interrupt.h): a `formfactors` or `render` run interrupted in
// its expensive stage stops within a second, exits 130 with one line, and leaves neither the
// output nor its temporary (F.mtx.tmp-<pid>) behind.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "test_util.h"

namespace daisy::test {
namespace {

struct Interrupted {
    int status = -1;
    double secondsAfterSignal = 0;
    std::string output;
};

// Starts daisy with `arguments`, sends `signal` after `delaySeconds`, waits for it.
Interrupted runAndSignal(const std::vector<std::string>& arguments, int signal, double delaySeconds,
                         const std::filesystem::path& log) {
    const pid_t child = fork();
    if (child == 0) {
        std::FILE* out = std::freopen(log.c_str(), "w", stderr);
        (void)out;
        dup2(fileno(stderr), fileno(stdout));
        std::vector<char*> argv{const_cast<char*>(DAISY_EXE_PATH)};
        for (const std::string& a : arguments)
            argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        execv(DAISY_EXE_PATH, argv.data());
        _exit(127);
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(delaySeconds));
    kill(child, signal);
    const auto sent = std::chrono::steady_clock::now();
    int raw = 0;
    waitpid(child, &raw, 0);
    Interrupted result;
    result.secondsAfterSignal =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    std::ifstream in(log);
    result.output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return result;
}

// Any file in `dir` whose name contains ".tmp-".
bool hasTemporary(const std::filesystem::path& dir) {
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (entry.path().filename().string().find(".tmp-") != std::string::npos) return true;
    }
    return false;
}

TEST(InterruptCli, SigintDuringFormFactorsExits130AndRemovesTheTemporary) {
    const auto dir = testTempDir();
    const auto matrix = dir / "F.mtx";
    // The Cornell box at --subdivide 0.02 takes several seconds of form factors.
    const Interrupted run =
        runAndSignal({"formfactors", assetPath("scenes/cornell_box.gltf"), "-o", matrix.string(),
                      "--subdivide", "0.02", "--quiet", "--no-cache"},
                     SIGINT, 1.0, dir / "log.txt");
    EXPECT_EQ(run.status, 130) << run.output;
    EXPECT_LT(run.secondsAfterSignal, 1.0);
    EXPECT_EQ(run.output, "error: interrupted by SIGINT; stopped, temporary files removed\n");
    EXPECT_FALSE(std::filesystem::exists(matrix));
    EXPECT_FALSE(hasTemporary(dir));
}

TEST(InterruptCli, SigtermDuringRenderExits130) {
    const auto dir = testTempDir();
    const auto image = dir / "out.png";
    const Interrupted run =
        runAndSignal({"render", assetPath("scenes/cornell_box.gltf"), "-o", image.string(),
                      "--subdivide", "0.02", "--quiet", "--no-cache"},
                     SIGTERM, 1.0, dir / "log.txt");
    EXPECT_EQ(run.status, 130) << run.output;
    EXPECT_LT(run.secondsAfterSignal, 1.0);
    EXPECT_EQ(run.output, "error: interrupted by SIGTERM; stopped, temporary files removed\n");
    EXPECT_FALSE(std::filesystem::exists(image));
    EXPECT_FALSE(hasTemporary(dir));
}

}  // namespace
}  // namespace daisy::test
