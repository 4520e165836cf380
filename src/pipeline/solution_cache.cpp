#include "pipeline/solution_cache.h"

#include <bit>
#include <cmath>
#include <span>
#include <system_error>
#include <type_traits>
#include <utility>

#include "core/cache_folder.h"
#include "core/check.h"
#include "core/strings.h"

namespace daisy {

static_assert(std::is_trivially_copyable_v<SolutionStats>, "stats are stored as raw bytes");

namespace {

const CacheFileFormat kFormat{
    {'D', 'A', 'I', 'S', 'Y', 'B', '\0', '\0'}, kSolutionCacheVersion, "solution cache file"};

// Bytes of the whole file for n patches, m samples and G present or not; false when the sizes
// cannot be a solution's (a corrupt header), before any allocation.
bool expectedFileBytes(const CacheFileHeader& header, bool gathered, uint64_t& bytes) {
    const uint64_t n = header.counts[0], m = header.counts[1];
    if (n > UINT32_MAX || m > 4096) return false;
    bytes = kCacheHeaderBytes + header.detail + n * m * 8 * (gathered ? 2 : 1);
    return true;
}

template <typename T>
void hashValues(Fnv1a128& hash, const std::vector<T>& values) {
    hash.updateU64(values.size());
    hash.update(std::as_bytes(std::span<const T>(values)));
}

}  // namespace

void hashRadiositySystem(Fnv1a128& hash, const RadiositySystem& system) {
    hash.updateU64(system.patchCount);
    hash.updateU64(system.wavelengthCount);
    hashValues(hash, system.wavelengthsNm);
    hashValues(hash, system.binWidthsNm);
    hashValues(hash, system.emission);
    hashValues(hash, system.areas);
    hashValues(hash, system.patchOperator);
    hash.updateU64(system.operators.size());
    for (const MaterialOperator& op : system.operators)
        hashValues(hash, op.matrix.values);
}

SolutionKey solutionKey(const FormFactorKey& formFactors, const RadiositySystem& system,
                        const SolverSettings& solver) {
    Fnv1a128 hash;
    hash.updateU64(kSolutionCacheVersion);
    hash.updateU64(formFactors.hi);
    hash.updateU64(formFactors.lo);
    hashRadiositySystem(hash, system);
    hash.updateText(solverKindName(solver.kind));
    hash.updateU64(std::bit_cast<uint64_t>(solver.tolerance));
    hash.updateU64(static_cast<uint64_t>(int64_t{solver.maxIterations}));
    return hash.digest();
}

SolutionCache::SolutionCache(std::filesystem::path directory, uint64_t sizeLimitBytes)
    : directory_(std::move(directory)), sizeLimitBytes_(sizeLimitBytes) {}

std::filesystem::path SolutionCache::entryPath(const SolutionKey& key) const {
    return directory_ / (key.hex() + ".dbr");
}

std::string SolutionCache::describe(const CacheFileHeader& header) {
    if (header.magic != kFormat.magic) return {};
    std::string text = concat("B: ", formatCount(header.counts[0]), " patches x ", header.counts[1],
                              " wavelengths (a converged solution)");
    if (header.version != kSolutionCacheVersion) {
        text += concat(" (format version ", header.version, ", this build reads ",
                       kSolutionCacheVersion, ")");
    }
    return text;
}

SolutionLookup SolutionCache::load(const SolutionKey& key, uint64_t patchCount,
                                   uint64_t wavelengthCount) const {
    const std::filesystem::path path = entryPath(key);
    const auto reject = [&](const std::string& what, bool removeFile = true) {
        SolutionLookup rejected;
        rejected.status = SolutionLookup::Status::Rejected;
        rejected.message = rejectCacheEntry(path, what, "solving", removeFile);
        return rejected;
    };
    CacheFileReader reader = CacheFileReader::open(path, kFormat, key);
    if (reader.status() == CacheFileReader::Status::Missing) return {};
    if (reader.status() == CacheFileReader::Status::Rejected) {
        return reject(reader.problem(), reader.removable());
    }
    const CacheFileHeader& header = reader.header();
    if (header.detail != sizeof(SolutionStats)) {
        return reject(concat("stats of ", header.detail, " bytes, this build's are ",
                             sizeof(SolutionStats), " (written by a different build)"));
    }
    // The key covers the patch and wavelength counts: other sizes are a damaged header.
    if (header.counts[0] != patchCount || header.counts[1] != wavelengthCount) {
        return reject(concat(header.counts[0], " patches x ", header.counts[1],
                             " wavelengths, the key's are ", patchCount, " x ", wavelengthCount,
                             " (file corrupt)"));
    }
    SolutionLookup lookup;
    if (!reader.read(&lookup.stats, sizeof(lookup.stats))) return reject(reader.finish());
    uint64_t expectedBytes = 0;
    if (lookup.stats.hasGathered > 1 ||
        !expectedFileBytes(header, lookup.stats.hasGathered != 0, expectedBytes)) {
        return reject("sizes out of range (file corrupt)");
    }
    if (reader.fileBytes() != expectedBytes) {
        return reject(concat("file is ", reader.fileBytes(), " bytes, its header says ",
                             expectedBytes, " (truncated or damaged)"));
    }
    const uint64_t values = patchCount * wavelengthCount;
    if (!reader.readArray(lookup.radiosity, values) ||
        (lookup.stats.hasGathered && !reader.readArray(lookup.gathered, values))) {
        return reject(reader.finish());
    }
    if (std::string problem = reader.finish(); !problem.empty()) return reject(problem);
    for (const std::vector<double>* array : {&lookup.radiosity, &lookup.gathered}) {
        for (double v : *array) {
            if (!std::isfinite(v)) return reject("a value that is not finite (file corrupt)");
        }
    }
    markCacheEntryUsed(path);
    lookup.status = SolutionLookup::Status::Hit;
    return lookup;
}

std::string SolutionCache::store(const SolutionKey& key, uint64_t patchCount,
                                 uint64_t wavelengthCount, const std::vector<double>& radiosity,
                                 const std::vector<double>& gathered,
                                 const SolutionStats& stats) const {
    DAISY_CHECK_OP(radiosity.size(), ==, patchCount * wavelengthCount);
    DAISY_CHECK(gathered.empty() || gathered.size() == radiosity.size());
    std::error_code error;
    std::filesystem::create_directories(directory_, error);
    if (error) {
        return concat("B not cached: cannot create the cache folder ", directory_.string(), ": ",
                      error.message());
    }
    CacheFileHeader header;
    header.magic = kFormat.magic;
    header.version = kFormat.version;
    header.detail = sizeof(SolutionStats);
    header.key = key;
    header.counts = {patchCount, wavelengthCount};
    SolutionStats stored = stats;
    stored.hasGathered = gathered.empty() ? 0 : 1;
    const std::span<const std::byte> payload[] = {bytesOf(stored), bytesOf(radiosity),
                                                  bytesOf(gathered)};
    const uint64_t limit =
        sizeLimitBytes_ != 0 ? sizeLimitBytes_ : defaultCacheSizeLimit(directory_);
    const uint64_t entryBytes = cacheFileBytes(payload);
    if (entryBytes > limit) {
        return concat("B not cached: its entry of ", formatBytes(double(entryBytes)),
                      " is over the cache size limit of ", formatBytes(double(limit)),
                      " (--cache-size)");
    }
    const std::filesystem::path path = entryPath(key);
    if (auto written = writeCacheFile(path, header, payload); !written) {
        return concat("B not cached: ", written.error().message);
    }
    pruneCacheFolder(directory_, limit, path);
    return {};
}

}  // namespace daisy
