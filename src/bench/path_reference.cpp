// The path-traced reference's chunk sums and cache file (path_reference.h), in the cache-file
// layer (core/cache_file.h): detail = chunks, counts = width and height; payload: seconds, the
// X Y Z sums and the variance sums (doubles).
#include "bench/path_reference.h"

#include <algorithm>
#include <fstream>
#include <iterator>

#include "core/cache_file.h"
#include "pathtrace/path_tracer.h"

namespace daisy::pathbench {
namespace {

const CacheFileFormat kFormat{
    {'D', 'A', 'I', 'S', 'Y', 'P', 'T', 'R'}, 1, "path-traced reference cache file"};

}  // namespace

Hash128 referenceKey(const std::string& scenePath, const std::string& settings) {
    Fnv1a128 hash;
    std::ifstream file(scenePath, std::ios::binary);
    const std::string bytes(std::istreambuf_iterator<char>(file), {});
    hash.updateText(bytes);
    hash.updateText(settings);
    return hash.digest();
}

bool readReference(const std::string& path, const Hash128& key, int width, int height,
                   Reference& r) {
    CacheFileReader in = CacheFileReader::open(path, kFormat, key);
    if (in.status() != CacheFileReader::Status::Open) return false;
    const CacheFileHeader& header = in.header();
    if (header.counts[0] != uint64_t(width) || header.counts[1] != uint64_t(height) ||
        header.detail < 1)
        return false;
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    Reference read;
    read.chunks = int(header.detail);
    if (!in.read(&read.seconds, sizeof read.seconds) || !in.readArray(read.xyzSum, pixels * 3) ||
        !in.readArray(read.varianceSum, pixels) || !in.finish().empty())
        return false;
    r = std::move(read);
    return true;
}

Expected<void> writeReference(const std::string& path, const Hash128& key, int width, int height,
                              const Reference& r) {
    CacheFileHeader header;
    header.magic = kFormat.magic;
    header.version = kFormat.version;
    header.detail = uint32_t(r.chunks);
    header.key = key;
    header.counts = {uint64_t(width), uint64_t(height)};
    const std::span<const std::byte> payload[] = {bytesOf(r.seconds), bytesOf(r.xyzSum),
                                                  bytesOf(r.varianceSum)};
    return writeCacheFile(path, header, payload);
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
