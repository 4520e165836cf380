#pragma once
// Helpers shared by the tests: a fresh temporary directory per test and small file writers.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace daisy::test {

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

inline std::string testDataPath(const std::string& relative) {
    return std::string(DAISY_TEST_DATA_DIR) + "/" + relative;
}

}  // namespace daisy::test
