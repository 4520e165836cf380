// The path-traced reference's chunk sums and cache file (path_reference.h). Layout: magic,
// key, width, height, chunks (int32), seconds, the X Y Z sums and the variance sums (doubles).
#include "bench/path_reference.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "core/atomic_file.h"
#include "pathtrace/path_tracer.h"

namespace daisy::pathbench {
namespace {

constexpr char kMagic[8] = {'D', 'R', 'P', 'T', 'R', 'E', 'F', '2'};

}  // namespace

uint64_t referenceKey(const std::string& scenePath, const std::string& settings) {
    uint64_t hash = 14695981039346656037ull;
    const auto mix = [&](const std::string& bytes) {
        for (unsigned char c : bytes)
            hash = (hash ^ c) * 1099511628211ull;
    };
    std::ifstream file(scenePath, std::ios::binary);
    mix(std::string(std::istreambuf_iterator<char>(file), {}));
    mix(settings);
    return hash;
}

bool readReference(const std::string& path, uint64_t key, int width, int height, Reference& r) {
    std::ifstream in(path, std::ios::binary);
    char magic[8];
    uint64_t stored = 0;
    int32_t header[3];
    if (!in.read(magic, 8) || !std::equal(magic, magic + 8, kMagic)) return false;
    if (!in.read(reinterpret_cast<char*>(&stored), 8) || stored != key) return false;
    if (!in.read(reinterpret_cast<char*>(header), 12) || header[0] != width ||
        header[1] != height || header[2] < 1)
        return false;
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    Reference read;
    read.chunks = header[2];
    read.xyzSum.resize(pixels * 3);
    read.varianceSum.resize(pixels);
    in.read(reinterpret_cast<char*>(&read.seconds), 8);
    in.read(reinterpret_cast<char*>(read.xyzSum.data()),
            std::streamsize(read.xyzSum.size() * sizeof(double)));
    in.read(reinterpret_cast<char*>(read.varianceSum.data()),
            std::streamsize(read.varianceSum.size() * sizeof(double)));
    if (!in) return false;
    r = std::move(read);
    return true;
}

Expected<void> writeReference(const std::string& path, uint64_t key, int width, int height,
                              const Reference& r) {
    return writeFileAtomically(path, [&](std::FILE* out) {
        const int32_t header[3] = {width, height, r.chunks};
        std::fwrite(kMagic, 1, 8, out);
        std::fwrite(&key, 8, 1, out);
        std::fwrite(header, 4, 3, out);
        std::fwrite(&r.seconds, 8, 1, out);
        std::fwrite(r.xyzSum.data(), sizeof(double), r.xyzSum.size(), out);
        std::fwrite(r.varianceSum.data(), sizeof(double), r.varianceSum.size(), out);
        return std::string();
    });
}

void finishReference(Reference& r, int width, int height, const std::vector<uint8_t>& mask) {
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    const double n = r.chunks;
    r.xyz = Image(width, height, 3);
    r.varianceY = Image(width, height, 1);
    Image withCoverage(width, height, 4);
    for (std::size_t p = 0; p < pixels; ++p) {
        for (int c = 0; c < 3; ++c) {
            r.xyz.pixels[p * 3 + c] = float(r.xyzSum[p * 3 + c] / n);
            withCoverage.pixels[p * 4 + c] = r.xyz.pixels[p * 3 + c];
        }
        withCoverage.pixels[p * 4 + 3] = 1;
        r.varianceY.pixels[p] = float(r.varianceSum[p] / (n * n));
    }
    r.noise = relativeRmsNoise(withCoverage, 1, r.varianceY, mask);
}

}  // namespace daisy::pathbench
