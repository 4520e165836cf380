#include "pipeline/formfactor_cache.h"

#include <bit>
#include <cstdlib>
#include <span>
#include <system_error>
#include <type_traits>
#include <utility>

#include "core/cache_folder.h"
#include "core/check.h"
#include "core/strings.h"

namespace daisy {

static_assert(std::is_trivially_copyable_v<FormFactorStats>, "stats are stored as raw bytes");

namespace {

const CacheFileFormat kFormat{
    {'D', 'A', 'I', 'S', 'Y', 'F', 'F', '\0'}, kFormFactorCacheVersion, "form-factor cache file"};

// The header's format-specific fields (core/cache_file.h).
uint64_t patchCountOf(const CacheFileHeader& header) {
    return header.counts[0];
}
uint64_t nonzeroCountOf(const CacheFileHeader& header) {
    return header.counts[1];
}

// What is wrong with the F-specific fields of a header the layer accepted, or "".
std::string headerProblem(const CacheFileHeader& header) {
    const uint64_t n = patchCountOf(header), nnz = nonzeroCountOf(header);
    if (header.detail != sizeof(FormFactorStats)) {
        return concat("stats of ", header.detail, " bytes, this build's are ",
                      sizeof(FormFactorStats), " (written by a different build)");
    }
    if (n > UINT32_MAX) return concat("patch count ", n, " is over 2^32 - 1 (file corrupt)");
    if (nnz > n * n) {
        return concat(nnz, " non-zeros for ", n, " patches, more than n^2 (file corrupt)");
    }
    return {};
}

// Bytes of the whole file the header describes. No overflow: n < 2^32 and nnz <= n^2 < 2^64
// are checked first, and the sum is computed in 128 bits and refused above 2^63.
bool expectedFileBytes(const CacheFileHeader& header, uint64_t& bytes) {
    const unsigned __int128 total = static_cast<unsigned __int128>(kCacheHeaderBytes) +
        header.detail + static_cast<unsigned __int128>(patchCountOf(header) + 1) * 8 +
        static_cast<unsigned __int128>(nonzeroCountOf(header)) * 8;
    if (total > (static_cast<unsigned __int128>(1) << 63)) return false;
    bytes = static_cast<uint64_t>(total);
    return true;
}

}  // namespace

FormFactorKey formFactorKey(const PatchMesh& patches, const FormFactorSettings& settings,
                            std::string_view backendFamily) {
    Fnv1a128 hash;
    hash.updateU64(kFormFactorCacheVersion);
    hash.updateText(backendFamily);
    hash.updateText(formFactorMethodName(settings.method));
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

FormFactorCache::FormFactorCache(std::filesystem::path directory, uint64_t sizeLimitBytes)
    : directory_(std::move(directory)), sizeLimitBytes_(sizeLimitBytes) {}

uint64_t FormFactorCache::sizeLimitBytes() const {
    return sizeLimitBytes_ != 0 ? sizeLimitBytes_ : defaultCacheSizeLimit(directory_);
}

std::string FormFactorCache::describe(const CacheFileHeader& header) {
    if (header.magic != kFormat.magic) return {};
    std::string text = concat("F: ", formatCount(patchCountOf(header)), " patches, ",
                              formatCount(nonzeroCountOf(header)), " non-zeros");
    if (header.version != kFormFactorCacheVersion) {
        text += concat(" (format version ", header.version, ", this build reads ",
                       kFormFactorCacheVersion, ")");
    }
    return text;
}

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
        rejected.message = rejectCacheEntry(path, what, "rebuilding", removeFile);
        return rejected;
    };

    CacheFileReader reader = CacheFileReader::open(path, kFormat, key);
    if (reader.status() == CacheFileReader::Status::Missing) return lookup;
    if (reader.status() == CacheFileReader::Status::Rejected) {
        return reject(reader.problem(), reader.removable());
    }
    const CacheFileHeader& header = reader.header();
    if (std::string problem = headerProblem(header); !problem.empty()) return reject(problem);
    uint64_t expectedBytes = 0;
    if (!expectedFileBytes(header, expectedBytes)) {
        return reject(concat("sizes overflow (", patchCountOf(header), " patches, ",
                             nonzeroCountOf(header), " non-zeros; file corrupt)"));
    }
    const uint64_t fileBytes = reader.fileBytes();
    const uint64_t matrixBytes = sparseMatrixBytes(patchCountOf(header), nonzeroCountOf(header));
    if (maxMemoryBytes != 0 && matrixBytes > maxMemoryBytes) {
        // A valid entry too large for this limit is kept; one whose size disagrees is corrupt.
        return reject(concat("the matrix as the header states it (", patchCountOf(header),
                             " patches, ", formatCount(nonzeroCountOf(header)),
                             " non-zeros) needs ", formatBytes(double(matrixBytes)),
                             ", over the memory limit of ", formatBytes(double(maxMemoryBytes))),
                      fileBytes != expectedBytes);
    }
    if (fileBytes != expectedBytes) {
        return reject(concat("file is ", fileBytes, " bytes, its header says ", expectedBytes,
                             " (truncated or damaged)"));
    }

    FormFactorStats stats;
    SparseMatrix matrix;
    matrix.size = static_cast<uint32_t>(patchCountOf(header));
    if (!reader.read(&stats, sizeof(stats)) ||
        !reader.readArray(matrix.rowOffsets, patchCountOf(header) + 1) ||
        !reader.readArray(matrix.columns, nonzeroCountOf(header)) ||
        !reader.readArray(matrix.values, nonzeroCountOf(header))) {
        return reject(reader.finish());  // "file ended early while reading (truncated)"
    }
    if (std::string problem = reader.finish(); !problem.empty()) return reject(problem);
    if (std::string problem = validateStructure(matrix); !problem.empty()) {
        return reject(concat("invalid matrix: ", problem));
    }
    markCacheEntryUsed(path);
    lookup.status = CacheLookup::Status::Hit;
    lookup.matrix = std::move(matrix);
    lookup.stats = stats;
    return lookup;
}

bool FormFactorCache::contains(const FormFactorKey& key) const {
    const CacheFileReader reader = CacheFileReader::open(entryPath(key), kFormat, key);
    uint64_t expectedBytes = 0;
    return reader.status() == CacheFileReader::Status::Open &&
        headerProblem(reader.header()).empty() &&
        expectedFileBytes(reader.header(), expectedBytes) && expectedBytes == reader.fileBytes();
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
    CacheFileHeader header;
    header.magic = kFormat.magic;
    header.version = kFormat.version;
    header.detail = sizeof(FormFactorStats);
    header.key = key;
    header.counts = {matrix.size, matrix.nonzeroCount()};
    const std::span<const std::byte> payload[] = {bytesOf(stats), bytesOf(matrix.rowOffsets),
                                                  bytesOf(matrix.columns), bytesOf(matrix.values)};
    const uint64_t entryBytes = cacheFileBytes(payload);
    const uint64_t limit = sizeLimitBytes();
    if (entryBytes > limit) {
        return concat("F not cached: its entry of ", formatBytes(double(entryBytes)),
                      " is over the cache size limit of ", formatBytes(double(limit)),
                      " (--cache-size)");
    }
    const std::filesystem::path path = entryPath(key);
    const auto written = writeCacheFile(path, header, payload);
    if (!written) return concat("F not cached: ", written.error().message);
    pruneCacheFolder(directory_, limit, path);
    return {};
}

}  // namespace daisy
