#pragma once
// Helpers shared by the tests: a fresh temporary directory per test and small file writers.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace daisy::test {

// The pid of a process that has exited and been reaped (for stale-temporary tests).
inline int deadPid() {
    const pid_t child = fork();
    if (child == 0) _exit(0);
    int status = 0;
    waitpid(child, &status, 0);
    return child;
}

// A directory unique to the running test, created empty, under the system temp directory.
inline std::filesystem::path testTempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "." + info->name();
    for (char& c : name) {
        if (c == '/') c = '_';
    }
    const auto dir = std::filesystem::temp_directory_path() / "daisy_tests" / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

// Writes `contents` to dir/name (binary-exact) and returns the full path as a string.
inline std::string writeFile(const std::filesystem::path& dir, const std::string& name,
                             const std::string& contents) {
    const auto path = dir / name;
    std::ofstream out(path, std::ios::binary);
    out << contents;
    return path.string();
}

// The bytes of the file at `path` ("" when it cannot be read).
inline std::string readBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Replaces the file at `path` with `bytes`.
inline void writeBytes(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << bytes;
}

// The names of the entries of `dir`, sorted.
inline std::vector<std::string> fileNames(const std::filesystem::path& dir) {
    std::vector<std::string> found;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        found.push_back(entry.path().filename().string());
    std::sort(found.begin(), found.end());
    return found;
}

struct RunResult {
    int status = -1;
    std::string output;  // stdout and stderr, interleaved
};

// The form-factor cache folder of the running test's `daisy` runs (XDG_CACHE_HOME/daisyriot):
// emptied when a test first uses it, so no test sees another's cached matrices, while the runs
// within one test share it.
inline std::filesystem::path testCacheHome() {
    const auto* unit = ::testing::UnitTest::GetInstance();
    const auto* info = unit->current_test_info();  // null in SetUpTestSuite
    const auto* suite = unit->current_test_suite();
    // A suite's set-up runs once in each process that runs one of its tests (ctest -j runs them
    // at once), so its folder is the process's own.
    std::string name = info
        ? std::string(info->test_suite_name()) + "." + info->name()
        : std::string(suite ? suite->name() : "global") + ".SetUp-" + std::to_string(::getpid());
    for (char& c : name) {
        if (c == '/') c = '_';
    }
    const auto dir = std::filesystem::temp_directory_path() / "daisy_tests_cache" / name;
    static std::string lastTest;
    if (lastTest != name) {
        std::filesystem::remove_all(dir);
        lastTest = name;
    }
    return dir;
}

// Runs the built `daisy` executable with `arguments` (shell words) and returns its exit status
// and output. Its default form-factor cache is the test's own (testCacheHome).
inline RunResult runDaisy(const std::string& arguments) {
    RunResult result;
    const std::string command = "XDG_CACHE_HOME='" + testCacheHome().string() + "' " +
        std::string(DAISY_EXE_PATH) + " " + arguments + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer;
    std::size_t count;
    while ((count = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) {
        result.output.append(buffer.data(), count);
    }
    const int raw = pclose(pipe);
    result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return result;
}

// A committed asset, e.g. assetPath("scenes/cornell_box.gltf").
inline std::string assetPath(const std::string& relative) {
    return std::string(DAISY_ASSETS_DIR) + "/" + relative;
}

inline std::string testDataPath(const std::string& relative) {
    return std::string(DAISY_TEST_DATA_DIR) + "/" + relative;
}

// DAISY_REQUIRE_VULKAN=1 (what .ci/run sets): the vulkan backend must run, so a test that would
// skip for want of a Vulkan device fails instead and CI cannot silently skip.
inline bool vulkanRequired() {
    const char* value = std::getenv("DAISY_REQUIRE_VULKAN");
    return value && std::strcmp(value, "1") == 0;
}

// DAISY_REQUIRE_CUDA=1 (what tools/gpu_check.sh sets on an NVIDIA machine): the cuda backend
// must run, so a test that would skip for want of a CUDA device fails instead.
inline bool cudaRequired() {
    const char* value = std::getenv("DAISY_REQUIRE_CUDA");
    return value && std::strcmp(value, "1") == 0;
}

}  // namespace daisy::test

// Skips the test with `reason` for want of a usable Vulkan device; fails it instead under
// DAISY_REQUIRE_VULKAN=1.
#define DAISY_SKIP_WITHOUT_VULKAN(reason)                                                       \
    do {                                                                                        \
        if (::daisy::test::vulkanRequired()) {                                                  \
            FAIL() << "DAISY_REQUIRE_VULKAN=1 but the vulkan backend cannot run: " << (reason); \
        }                                                                                       \
        GTEST_SKIP() << "no usable Vulkan device: " << (reason);                                \
    } while (0)

// Skips the test with `reason` for want of a usable CUDA device (or a build without nvcc); fails
// it instead under DAISY_REQUIRE_CUDA=1.
#define DAISY_SKIP_WITHOUT_CUDA(reason)                                                     \
    do {                                                                                    \
        if (::daisy::test::cudaRequired()) {                                                \
            FAIL() << "DAISY_REQUIRE_CUDA=1 but the cuda backend cannot run: " << (reason); \
        }                                                                                   \
        GTEST_SKIP() << "no usable CUDA device: " << (reason);                              \
    } while (0)
