#pragma once
// Disk cache of the view-factor matrix F (DESIGN.md section 1; format and policy in
// docs/cache.md). An entry is one file "<key hex>.dff" in the cache folder: a 64-byte
// little-endian header (magic, format version, key, sizes, checksums), then the FormFactorStats
// bytes and the CSR arrays. Every entry is fully verified on load and rejected (then removed)
// when any check fails, so a corrupt, truncated or foreign file costs a rebuild, never a wrong F.
// Written atomically (core/atomic_file.h): a crash leaves the old entry or none, never a partial.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "geometry/patch_mesh.h"
#include "radiosity/form_factors.h"
#include "radiosity/sparse_matrix.h"

namespace daisy {

// Bump when the key's byte stream, the file layout or FormFactorStats' field meaning changes:
// older entries then miss (different key) or are rejected (different version in the header).
// 2: per-pair end clearance (issue 18); 3: kernel-weighted visibility (issue 18).
inline constexpr uint32_t kFormFactorCacheVersion = 3;

// 128-bit key of exactly what F depends on, and nothing else.
struct FormFactorKey {
    uint64_t hi = 0, lo = 0;
    std::string hex() const;  // 32 lowercase hex digits, hi first; used as the file name
    bool operator==(const FormFactorKey&) const = default;
};

// Hash of: the patch geometry after subdivision (every patch's three corner positions in patch
// order, as their exact double bits; the patch count), settings.method, quadratureLevel,
// raysPerPair, stochasticRays (only when method is stochastic), seed, shaftCulling (it changes F
// within float rounding), the backend family string ("cpu" or "kernel"), and
// kFormFactorCacheVersion. NOT materials, emission, cameras, threads, maxMemoryBytes, progress,
// wavelengths. Deterministic across runs and machines (no std::hash): 128-bit FNV-1a over the
// byte stream listed in docs/cache.md. About 72 bytes per patch (~1 ms for 7,712 patches).
FormFactorKey formFactorKey(const PatchMesh& patches, const FormFactorSettings& settings,
                            std::string_view backendFamily);

// 128-bit FNV-1a (Fowler, Noll, Vo; IETF draft-eastlake-fnv: offset basis
// 0x6c62272e07bb014262b821756295c58d, prime 2^88 + 0x13b), byte by byte. The key's hash.
class Fnv1a128 {
public:
    void update(std::span<const std::byte> bytes);
    void updateU64(uint64_t value);  // its 8 bytes, least significant first
    FormFactorKey digest() const { return {hi_, lo_}; }

private:
    uint64_t hi_ = 0x6c62272e07bb0142ull, lo_ = 0x62b821756295c58dull;
};

// XXH64 (Y. Collet, xxHash specification v0.8, doc/xxhash_spec.md in github.com/Cyan4973/
// xxHash), streaming: the same digest however the input is split. The file's checksums.
class Xxh64 {
public:
    explicit Xxh64(uint64_t seed = 0);
    void update(std::span<const std::byte> bytes);
    uint64_t digest() const;

private:
    uint64_t lanes_[4];
    uint64_t seed_;
    uint64_t totalBytes_ = 0;
    std::byte buffer_[32];  // input not yet consumed as a 32-byte stripe
    std::size_t buffered_ = 0;
};

// One-shot XXH64 of `bytes` with `seed`.
uint64_t xxh64(std::span<const std::byte> bytes, uint64_t seed = 0);

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
    static constexpr std::size_t kHeaderBytes = 64;
    static constexpr std::size_t kHeaderChecksummedBytes = 56;

    explicit FormFactorCache(std::filesystem::path directory);
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
    // Miss when no entry file exists.
    CacheLookup load(const FormFactorKey& key, uint64_t maxMemoryBytes = 0) const;
    // Cheap: true when an entry file exists whose header matches key and whose file size matches
    // the header (no checksum pass). For `daisy info` ("F is cached").
    bool contains(const FormFactorKey& key) const;
    // Writes the entry atomically (temporary sibling, flush, rename), creating the directory.
    // Failure (read-only or full folder, cannot create directory) is NOT an error for the caller:
    // returns a one-line warning message naming the folder and the cause, or an empty string on
    // success. Never leaves a partial entry or temp file behind. The matrix must be well formed
    // (DAISY_CHECK on its array sizes). Not for concurrent stores of one key within one process.
    std::string store(const FormFactorKey& key, const SparseMatrix& matrix,
                      const FormFactorStats& stats) const;

private:
    std::filesystem::path directory_;
};

}  // namespace daisy
