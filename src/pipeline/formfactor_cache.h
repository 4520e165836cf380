#pragma once
// Disk cache of the view-factor matrix F (DESIGN.md section 1; format and policy in
// docs/cache.md). An entry is one file "<key hex>.dff" in the cache folder, in the layout of
// core/cache_file.h (magic "DAISYFF", detail = sizeof(FormFactorStats), counts = patch count
// and non-zeros), its payload the FormFactorStats bytes and the CSR arrays. Every entry is fully
// verified on load and rejected (then removed) when any check fails, so a corrupt, truncated or
// foreign file costs a rebuild, never a wrong F. Written atomically: a crash leaves the old
// entry or none, never a partial. The folder is kept under a size limit by evicting the least
// recently used entries after each store (core/cache_folder.h).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/cache_file.h"
#include "geometry/patch_mesh.h"
#include "radiosity/form_factors.h"
#include "radiosity/sparse_matrix.h"

namespace daisy {

// Bump when the key's byte stream, the file layout or FormFactorStats' field meaning changes:
// older entries then miss (different key) or are rejected (different version in the header).
// 2: per-pair end clearance; 3: kernel-weighted visibility; 4: the cpu backend's watertight
// segments; 5: the cost model's fixed prices (its stats, and its choices: F); 6: the hybrid
// kernel's absolute tolerance (DAISY_FF_ABS_TOL).
inline constexpr uint32_t kFormFactorCacheVersion = 6;

// 128-bit key of exactly what F depends on, and nothing else (hex() names the file).
using FormFactorKey = Hash128;

// Hash of: the patch geometry after subdivision (every patch's three corner positions in patch
// order, as their exact double bits; the patch count), settings.method, quadratureLevel,
// raysPerPair, stochasticRays (only when method is stochastic), seed, shaftCulling (it changes F
// within float rounding), the backend family string ("cpu" or "kernel"), and
// kFormFactorCacheVersion. NOT materials, emission, cameras, threads, maxMemoryBytes, progress,
// wavelengths. Deterministic across runs and machines (no std::hash): 128-bit FNV-1a over the
// byte stream listed in docs/cache.md. About 72 bytes per patch (~1 ms for 7,712 patches).
FormFactorKey formFactorKey(const PatchMesh& patches, const FormFactorSettings& settings,
                            std::string_view backendFamily);

struct CacheLookup {
    enum class Status { Hit, Miss, Rejected };
    Status status = Status::Miss;
    SparseMatrix matrix;  // on Hit
    FormFactorStats stats;  // on Hit: the stats stored with the matrix (radiosity/form_factors.h)
    std::string message;  // on Rejected: ONE line naming the file and what is wrong
                          // (".../<hex>.dff: checksum mismatch (file corrupt); rebuilding")
};

class FormFactorCache {
public:
    // Entry file layout: header bytes, of which the first kHeaderChecksummedBytes are covered by
    // the header checksum stored right after them (docs/cache.md has the field table).
    static constexpr std::size_t kHeaderBytes = kCacheHeaderBytes;
    static constexpr std::size_t kHeaderChecksummedBytes = kCacheHeaderChecksummedBytes;

    // `sizeLimitBytes`: the folder's size limit that store() keeps (0 = the default,
    // defaultCacheSizeLimit of core/cache_folder.h, computed at each store).
    explicit FormFactorCache(std::filesystem::path directory, uint64_t sizeLimitBytes = 0);
    // $XDG_CACHE_HOME/daisyriot when XDG_CACHE_HOME is set and absolute, else
    // $HOME/.cache/daisyriot; empty when HOME is unset or relative too (then run without a cache).
    static std::filesystem::path defaultDirectory();
    const std::filesystem::path& directory() const { return directory_; }
    std::filesystem::path entryPath(const FormFactorKey& key) const;  // directory / "<hex>.dff"
    // Reads and fully verifies an entry (magic, version, key, sizes, checksum, CSR structure via
    // validateStructure from radiosity/sparse_matrix.h). A file that fails any check is Rejected
    // (and removed, best effort), never trusted. Refuses (Rejected with a message) to allocate more
    // than maxMemoryBytes (0 = no limit) for the matrix as the header states it; such a file is
    // kept when its size agrees with its header (a valid entry, too large for this limit).
    // Miss when no entry file exists. A hit marks the entry as used now (its modification
    // time), which is what least-recently-used eviction orders by.
    CacheLookup load(const FormFactorKey& key, uint64_t maxMemoryBytes = 0) const;
    // Cheap: true when an entry file exists whose header matches key and whose file size matches
    // the header (no checksum pass). For `daisy info` ("F is cached").
    bool contains(const FormFactorKey& key) const;
    // Writes the entry atomically (temporary sibling, flush, rename), creating the directory.
    // Failure (read-only or full folder, cannot create directory) is NOT an error for the caller:
    // returns a one-line warning message naming the folder and the cause, or an empty string on
    // success. Never leaves a partial entry or temp file behind. The matrix must be well formed
    // (DAISY_CHECK on its array sizes). Not for concurrent stores of one key within one process.
    // An entry larger than the size limit is not written (a one-line message says so); after a
    // write, stale temporaries are removed and the least recently used other entries evicted
    // until the folder is under the limit (pruneCacheFolder).
    std::string store(const FormFactorKey& key, const SparseMatrix& matrix,
                      const FormFactorStats& stats) const;

    // The size limit store() keeps: the one given, else the default for the folder.
    uint64_t sizeLimitBytes() const;

    // A one-line summary of an F entry's header for `daisy cache list` ("F: 7,712 patches,
    // 27,911,000 non-zeros"), or "" when the header is not an F entry's (another magic).
    static std::string describe(const CacheFileHeader& header);

private:
    std::filesystem::path directory_;
    uint64_t sizeLimitBytes_ = 0;
};

}  // namespace daisy
