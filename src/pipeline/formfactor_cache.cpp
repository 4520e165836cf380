#include "pipeline/formfactor_cache.h"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/atomic_file.h"
#include "core/check.h"
#include "core/memory.h"
#include "core/strings.h"

namespace daisy {

// The payload arrays are written and read as the host's bytes; the format is little-endian.
static_assert(std::endian::native == std::endian::little, "the F cache format is little-endian");
static_assert(std::is_trivially_copyable_v<FormFactorStats>, "stats are stored as raw bytes");

namespace {

constexpr std::array<char, 8> kMagic = {'D', 'A', 'I', 'S', 'Y', 'F', 'F', '\0'};

template <typename T>
std::span<const std::byte> bytesOf(const T& value) {
    return std::as_bytes(std::span<const T, 1>(&value, 1));
}

template <typename T, typename Allocator>
std::span<const std::byte> bytesOf(const std::vector<T, Allocator>& values) {
    return std::as_bytes(std::span<const T>(values));
}

uint64_t rotl(uint64_t x, int r) {
    return std::rotl(x, r);
}

// XXH64 constants and steps (xxHash specification v0.8, section "XXH64 algorithm").
constexpr uint64_t kPrime1 = 0x9E3779B185EBCA87ull;
constexpr uint64_t kPrime2 = 0xC2B2AE3D27D4EB4Full;
constexpr uint64_t kPrime3 = 0x165667B19E3779F9ull;
constexpr uint64_t kPrime4 = 0x85EBCA77C2B2AE63ull;
constexpr uint64_t kPrime5 = 0x27D4EB2F165667C5ull;

uint64_t xxhRound(uint64_t accumulator, uint64_t lane) {
    return rotl(accumulator + lane * kPrime2, 31) * kPrime1;
}

uint64_t xxhMerge(uint64_t accumulator, uint64_t lane) {
    return (accumulator ^ xxhRound(0, lane)) * kPrime1 + kPrime4;
}

uint64_t readU64(const std::byte* p) {
    uint64_t value;
    std::memcpy(&value, p, 8);
    return value;
}

uint32_t readU32(const std::byte* p) {
    uint32_t value;
    std::memcpy(&value, p, 4);
    return value;
}

// The fixed 64-byte header (docs/cache.md, "File format").
struct Header {
    std::array<char, 8> magic{};
    uint32_t version = 0;
    uint32_t statsBytes = 0;
    FormFactorKey key;
    uint64_t patchCount = 0;
    uint64_t nonzeroCount = 0;
    uint64_t payloadChecksum = 0;
    uint64_t headerChecksum = 0;
};

using HeaderBytes = std::array<std::byte, FormFactorCache::kHeaderBytes>;

HeaderBytes encodeHeader(const Header& header) {
    HeaderBytes bytes{};
    std::memcpy(bytes.data() + 0, header.magic.data(), 8);
    std::memcpy(bytes.data() + 8, &header.version, 4);
    std::memcpy(bytes.data() + 12, &header.statsBytes, 4);
    std::memcpy(bytes.data() + 16, &header.key.hi, 8);
    std::memcpy(bytes.data() + 24, &header.key.lo, 8);
    std::memcpy(bytes.data() + 32, &header.patchCount, 8);
    std::memcpy(bytes.data() + 40, &header.nonzeroCount, 8);
    std::memcpy(bytes.data() + 48, &header.payloadChecksum, 8);
    const uint64_t checksum =
        xxh64(std::span(bytes.data(), FormFactorCache::kHeaderChecksummedBytes));
    std::memcpy(bytes.data() + 56, &checksum, 8);
    return bytes;
}

Header decodeHeader(const HeaderBytes& bytes) {
    Header header;
    std::memcpy(header.magic.data(), bytes.data(), 8);
    header.version = readU32(bytes.data() + 8);
    header.statsBytes = readU32(bytes.data() + 12);
    header.key.hi = readU64(bytes.data() + 16);
    header.key.lo = readU64(bytes.data() + 24);
    header.patchCount = readU64(bytes.data() + 32);
    header.nonzeroCount = readU64(bytes.data() + 40);
    header.payloadChecksum = readU64(bytes.data() + 48);
    header.headerChecksum = readU64(bytes.data() + 56);
    return header;
}

// What is wrong with the header for `key`, or "" when it is ours; checks in the order that
// gives the most useful message (a future version may move the checksum, so version first).
std::string headerProblem(const Header& header, const HeaderBytes& bytes,
                          const FormFactorKey& key) {
    if (header.magic != kMagic) return "not a DaisyRiot form-factor cache file (bad magic)";
    if (header.version != kFormFactorCacheVersion) {
        return concat("format version ", header.version, ", this build reads version ",
                      kFormFactorCacheVersion);
    }
    if (xxh64(std::span(bytes.data(), FormFactorCache::kHeaderChecksummedBytes)) !=
        header.headerChecksum) {
        return "header checksum mismatch (file corrupt)";
    }
    if (header.key != key) {
        return concat("holds the entry for key ", header.key.hex(), ", not ", key.hex(),
                      " (renamed or copied file)");
    }
    if (header.statsBytes != sizeof(FormFactorStats)) {
        return concat("stats of ", header.statsBytes, " bytes, this build's are ",
                      sizeof(FormFactorStats), " (written by a different build)");
    }
    if (header.patchCount > UINT32_MAX) {
        return concat("patch count ", header.patchCount, " is over 2^32 - 1 (file corrupt)");
    }
    if (header.nonzeroCount > header.patchCount * header.patchCount) {
        return concat(header.nonzeroCount, " non-zeros for ", header.patchCount,
                      " patches, more than n^2 (file corrupt)");
    }
    return {};
}

// Bytes of the whole file the header describes. No overflow: n < 2^32 and nnz <= n^2 < 2^64
// are checked first, and the sum is computed in 128 bits and refused above 2^63.
bool expectedFileBytes(const Header& header, uint64_t& bytes) {
    const unsigned __int128 total = static_cast<unsigned __int128>(FormFactorCache::kHeaderBytes) +
        header.statsBytes + static_cast<unsigned __int128>(header.patchCount + 1) * 8 +
        static_cast<unsigned __int128>(header.nonzeroCount) * 8;
    if (total > (static_cast<unsigned __int128>(1) << 63)) return false;
    bytes = static_cast<uint64_t>(total);
    return true;
}

struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

bool readExactly(std::FILE* file, void* data, std::size_t bytes) {
    return bytes == 0 || std::fread(data, 1, bytes, file) == bytes;
}

// Into storage advised for huge pages (core/memory.h): F's arrays are hundreds of MB, and the
// read's copy into 4 KiB pages took a page fault each (a virtual machine's exit).
template <typename T, typename Allocator>
bool readArray(std::FILE* file, std::vector<T, Allocator>& values, uint64_t count) {
    resizeOnHugePages(values, count);
    return readExactly(file, values.data(), count * sizeof(T));
}

// The size of an open regular file, or what is wrong with it.
std::string regularFileBytes(std::FILE* file, uint64_t& bytes) {
    struct stat info;
    if (fstat(fileno(file), &info) != 0) return concat("cannot read: ", std::strerror(errno));
    if (!S_ISREG(info.st_mode)) return "not a regular file";
    bytes = static_cast<uint64_t>(info.st_size);
    return {};
}

bool writeBytes(std::FILE* file, std::span<const std::byte> bytes) {
    return bytes.empty() || std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
}

uint64_t payloadChecksum(const FormFactorStats& stats, const SparseMatrix& matrix) {
    Xxh64 hash;
    hash.update(bytesOf(stats));
    hash.update(bytesOf(matrix.rowOffsets));
    hash.update(bytesOf(matrix.columns));
    hash.update(bytesOf(matrix.values));
    return hash.digest();
}

}  // namespace

std::string FormFactorKey::hex() const {
    static constexpr char kDigits[] = "0123456789abcdef";
    std::string text(32, '0');
    for (int k = 0; k < 16; ++k) {
        text[15 - k] = kDigits[(hi >> (4 * k)) & 0xf];
        text[31 - k] = kDigits[(lo >> (4 * k)) & 0xf];
    }
    return text;
}

void Fnv1a128::update(std::span<const std::byte> bytes) {
    for (std::byte b : bytes) {
        // h = (h ^ b) * (2^88 + 0x13b) mod 2^128 = h * 0x13b + (h << 88).
        const uint64_t lo = lo_ ^ std::to_integer<uint64_t>(b);
        const unsigned __int128 low = static_cast<unsigned __int128>(lo) * 0x13bu;
        lo_ = static_cast<uint64_t>(low);
        hi_ = hi_ * 0x13bu + static_cast<uint64_t>(low >> 64) + (lo << 24);
    }
}

void Fnv1a128::updateU64(uint64_t value) {
    std::array<std::byte, 8> bytes;
    std::memcpy(bytes.data(), &value, 8);  // little-endian host (static_assert above)
    update(bytes);
}

Xxh64::Xxh64(uint64_t seed)
    : lanes_{seed + kPrime1 + kPrime2, seed + kPrime2, seed, seed - kPrime1}, seed_(seed) {}

void Xxh64::update(std::span<const std::byte> bytes) {
    if (bytes.empty()) return;  // data() may be null
    totalBytes_ += bytes.size();
    const std::byte* p = bytes.data();
    std::size_t left = bytes.size();
    const auto stripe = [this](const std::byte* s) {
        for (int k = 0; k < 4; ++k)
            lanes_[k] = xxhRound(lanes_[k], readU64(s + 8 * k));
    };
    if (buffered_ > 0) {
        const std::size_t take = std::min(left, sizeof(buffer_) - buffered_);
        std::memcpy(buffer_ + buffered_, p, take);
        buffered_ += take;
        p += take;
        left -= take;
        if (buffered_ < sizeof(buffer_)) return;
        stripe(buffer_);
        buffered_ = 0;
    }
    for (; left >= 32; p += 32, left -= 32)
        stripe(p);
    if (left > 0) std::memcpy(buffer_, p, left);
    buffered_ = left;
}

uint64_t Xxh64::digest() const {
    uint64_t acc;
    if (totalBytes_ >= 32) {
        acc = rotl(lanes_[0], 1) + rotl(lanes_[1], 7) + rotl(lanes_[2], 12) + rotl(lanes_[3], 18);
        for (uint64_t lane : lanes_)
            acc = xxhMerge(acc, lane);
    } else {
        acc = seed_ + kPrime5;
    }
    acc += totalBytes_;
    const std::byte* p = buffer_;
    std::size_t left = buffered_;
    for (; left >= 8; p += 8, left -= 8)
        acc = rotl(acc ^ xxhRound(0, readU64(p)), 27) * kPrime1 + kPrime4;
    if (left >= 4) {
        acc = rotl(acc ^ (uint64_t(readU32(p)) * kPrime1), 23) * kPrime2 + kPrime3;
        p += 4;
        left -= 4;
    }
    for (; left > 0; ++p, --left)
        acc = rotl(acc ^ (std::to_integer<uint64_t>(*p) * kPrime5), 11) * kPrime1;
    acc ^= acc >> 33;
    acc *= kPrime2;
    acc ^= acc >> 29;
    acc *= kPrime3;
    acc ^= acc >> 32;
    return acc;
}

uint64_t xxh64(std::span<const std::byte> bytes, uint64_t seed) {
    Xxh64 hash(seed);
    hash.update(bytes);
    return hash.digest();
}

FormFactorKey formFactorKey(const PatchMesh& patches, const FormFactorSettings& settings,
                            std::string_view backendFamily) {
    Fnv1a128 hash;
    const auto text = [&hash](std::string_view s) {
        hash.updateU64(s.size());
        hash.update(std::as_bytes(std::span(s.data(), s.size())));
    };
    hash.updateU64(kFormFactorCacheVersion);
    text(backendFamily);
    text(formFactorMethodName(settings.method));
    hash.updateU64(static_cast<uint64_t>(int64_t{settings.quadratureLevel}));
    hash.updateU64(static_cast<uint64_t>(int64_t{settings.raysPerPair}));
    hash.updateU64(settings.seed);
    hash.updateU64(settings.shaftCulling ? 1 : 0);
    if (settings.method == FormFactorMethod::Stochastic) {
        hash.updateU64(static_cast<uint64_t>(int64_t{settings.stochasticRays}));
    }
    hash.updateU64(patches.patchCount());
    for (const auto& corners : patches.patches) {
        for (uint32_t vertex : corners) {
            const Vec3d& p = patches.positions[vertex];
            hash.updateU64(std::bit_cast<uint64_t>(p.x));
            hash.updateU64(std::bit_cast<uint64_t>(p.y));
            hash.updateU64(std::bit_cast<uint64_t>(p.z));
        }
    }
    return hash.digest();
}

FormFactorCache::FormFactorCache(std::filesystem::path directory)
    : directory_(std::move(directory)) {}

std::filesystem::path FormFactorCache::defaultDirectory() {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    if (xdg != nullptr && std::filesystem::path(xdg).is_absolute()) {
        return std::filesystem::path(xdg) / "daisyriot";
    }
    const char* home = std::getenv("HOME");
    if (home != nullptr && std::filesystem::path(home).is_absolute()) {
        return std::filesystem::path(home) / ".cache" / "daisyriot";
    }
    return {};
}

std::filesystem::path FormFactorCache::entryPath(const FormFactorKey& key) const {
    return directory_ / (key.hex() + ".dff");
}

CacheLookup FormFactorCache::load(const FormFactorKey& key, uint64_t maxMemoryBytes) const {
    const std::filesystem::path path = entryPath(key);
    CacheLookup lookup;
    const auto reject = [&](const std::string& what, bool removeFile = true) {
        CacheLookup rejected;
        rejected.status = CacheLookup::Status::Rejected;
        rejected.message = concat(path.string(), ": ", what, "; rebuilding");
        if (removeFile) {
            std::error_code ignored;
            std::filesystem::remove(path, ignored);
        }
        return rejected;
    };

    const File file(std::fopen(path.c_str(), "rb"));
    if (!file && (errno == ENOENT || errno == ENOTDIR)) return lookup;  // no entry (or folder)
    if (!file) return reject(concat("cannot read: ", std::strerror(errno)), false);
    // The size of the file opened, not of the path: a concurrent store may rename over it.
    uint64_t fileBytes = 0;
    if (std::string problem = regularFileBytes(file.get(), fileBytes); !problem.empty()) {
        return reject(problem, false);
    }
    if (fileBytes == 0) return reject("empty file");
    if (fileBytes < kHeaderBytes) {
        return reject(concat("truncated header (", fileBytes, " of ", kHeaderBytes, " bytes)"));
    }
    HeaderBytes headerBytes;
    if (!readExactly(file.get(), headerBytes.data(), headerBytes.size())) {
        return reject("cannot read the header");
    }
    const Header header = decodeHeader(headerBytes);
    if (std::string problem = headerProblem(header, headerBytes, key); !problem.empty()) {
        return reject(problem);
    }
    uint64_t expectedBytes = 0;
    if (!expectedFileBytes(header, expectedBytes)) {
        return reject(concat("sizes overflow (", header.patchCount, " patches, ",
                             header.nonzeroCount, " non-zeros; file corrupt)"));
    }
    const uint64_t matrixBytes = sparseMatrixBytes(header.patchCount, header.nonzeroCount);
    if (maxMemoryBytes != 0 && matrixBytes > maxMemoryBytes) {
        // A valid entry too large for this limit is kept; one whose size disagrees is corrupt.
        return reject(concat("the matrix as the header states it (", header.patchCount,
                             " patches, ", formatCount(header.nonzeroCount), " non-zeros) needs ",
                             formatBytes(double(matrixBytes)), ", over the memory limit of ",
                             formatBytes(double(maxMemoryBytes))),
                      fileBytes != expectedBytes);
    }
    if (fileBytes != expectedBytes) {
        return reject(concat("file is ", fileBytes, " bytes, its header says ", expectedBytes,
                             " (truncated or damaged)"));
    }

    FormFactorStats stats;
    SparseMatrix matrix;
    matrix.size = static_cast<uint32_t>(header.patchCount);
    if (!readExactly(file.get(), &stats, sizeof(stats)) ||
        !readArray(file.get(), matrix.rowOffsets, header.patchCount + 1) ||
        !readArray(file.get(), matrix.columns, header.nonzeroCount) ||
        !readArray(file.get(), matrix.values, header.nonzeroCount)) {
        return reject("file ended early while reading (truncated)");
    }
    if (payloadChecksum(stats, matrix) != header.payloadChecksum) {
        return reject("payload checksum mismatch (file corrupt)");
    }
    if (std::string problem = validateStructure(matrix); !problem.empty()) {
        return reject(concat("invalid matrix: ", problem));
    }
    lookup.status = CacheLookup::Status::Hit;
    lookup.matrix = std::move(matrix);
    lookup.stats = stats;
    return lookup;
}

bool FormFactorCache::contains(const FormFactorKey& key) const {
    const std::filesystem::path path = entryPath(key);
    const File file(std::fopen(path.c_str(), "rb"));
    uint64_t fileBytes = 0;
    HeaderBytes headerBytes;
    if (!file || !regularFileBytes(file.get(), fileBytes).empty() || fileBytes < kHeaderBytes ||
        !readExactly(file.get(), headerBytes.data(), headerBytes.size())) {
        return false;
    }
    const Header header = decodeHeader(headerBytes);
    uint64_t expectedBytes = 0;
    return headerProblem(header, headerBytes, key).empty() &&
        expectedFileBytes(header, expectedBytes) && expectedBytes == fileBytes;
}

std::string FormFactorCache::store(const FormFactorKey& key, const SparseMatrix& matrix,
                                   const FormFactorStats& stats) const {
    DAISY_CHECK(matrix.rowOffsets.size() == uint64_t(matrix.size) + 1);
    DAISY_CHECK(matrix.columns.size() == matrix.values.size());
    DAISY_CHECK(matrix.rowOffsets.back() == matrix.columns.size());
    std::error_code error;
    std::filesystem::create_directories(directory_, error);
    if (error) {
        return concat("F not cached: cannot create the cache folder ", directory_.string(), ": ",
                      error.message());
    }
    Header header;
    header.magic = kMagic;
    header.version = kFormFactorCacheVersion;
    header.statsBytes = sizeof(FormFactorStats);
    header.key = key;
    header.patchCount = matrix.size;
    header.nonzeroCount = matrix.nonzeroCount();
    header.payloadChecksum = payloadChecksum(stats, matrix);
    const HeaderBytes headerBytes = encodeHeader(header);
    const auto written = writeFileAtomically(entryPath(key).string(), [&](std::FILE* file) {
        const bool ok = writeBytes(file, headerBytes) && writeBytes(file, bytesOf(stats)) &&
            writeBytes(file, bytesOf(matrix.rowOffsets)) &&
            writeBytes(file, bytesOf(matrix.columns)) && writeBytes(file, bytesOf(matrix.values));
        return ok ? std::string() : concat("write failed: ", std::strerror(errno));
    });
    if (!written) return concat("F not cached: ", written.error().message);
    return {};
}

}  // namespace daisy
