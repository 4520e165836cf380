#pragma once
// The path-traced reference's chunk sums and their disk cache (bench/path_bench.h), internal to
// src/bench/.
#include <cstdint>
#include <string>
#include <vector>

#include "core/cache_file.h"
#include "core/expected.h"
#include "image/image.h"

namespace daisy::pathbench {

// The reference's chunk sums (what the cache holds) and the mean they give.
struct Reference {
    int chunks = 0;
    double seconds = 0;
    std::vector<double> xyzSum;  // per pixel X Y Z, summed over chunks
    std::vector<double> varianceSum;  // per pixel, the chunks' variances of their mean Y, summed
    Image xyz;  // the mean, 3 channels
    Image varianceY;  // of the mean: varianceSum / chunks^2
    double noise = 0;  // relative RMS noise over the kept pixels
};

// FNV-1a 128 of the scene file's bytes, then of `settings`.
Hash128 referenceKey(const std::string& scenePath, const std::string& settings);

// The cache (core/cache_file.h): false (and `r` untouched) when the file is missing, damaged,
// another key's or another size's.
bool readReference(const std::string& path, const Hash128& key, int width, int height,
                   Reference& r);
Expected<void> writeReference(const std::string& path, const Hash128& key, int width, int height,
                              const Reference& r);

// The mean of the chunks, its variance and its relative RMS noise over `mask`.
void finishReference(Reference& r, int width, int height, const std::vector<uint8_t>& mask);

}  // namespace daisy::pathbench
