#pragma once
// What the file-based fuzz targets share: a private scratch folder (one per process, so parallel
// fuzzers never collide) and a writer. Header-only, included by each tests/fuzz/*_fuzz.cpp.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

namespace daisy::fuzz {

inline const std::filesystem::path& scratchDir() {
    static const std::filesystem::path dir = [] {
        auto path =
            std::filesystem::temp_directory_path() / ("daisy_fuzz_" + std::to_string(getpid()));
        std::filesystem::create_directories(path);
        return path;
    }();
    return dir;
}

inline std::string writeScratch(const std::string& name, std::string_view bytes) {
    const std::string path = (scratchDir() / name).string();
    if (std::FILE* file = std::fopen(path.c_str(), "wb")) {
        std::fwrite(bytes.data(), 1, bytes.size(), file);
        std::fclose(file);
    }
    return path;
}

// Splits `bytes` at the first occurrence of `separator`: {before, after} (after empty if none).
inline std::pair<std::string_view, std::string_view> splitAt(std::string_view bytes,
                                                             std::string_view separator) {
    const std::size_t at = bytes.find(separator);
    if (at == std::string_view::npos) return {bytes, {}};
    return {bytes.substr(0, at), bytes.substr(at + separator.size())};
}

// Loader memory cap for the fuzzers: large enough for every seed, small enough that a hostile
// accessor count is refused quickly instead of exhausting the fuzzer's RSS limit.
inline constexpr uint64_t kFuzzMaxMemoryBytes = uint64_t(256) << 20;

}  // namespace daisy::fuzz
