#pragma once
// The binary file layer of every disk cache (the F cache of pipeline/formfactor_cache.h, the
// bench references): one 64-byte little-endian header, the hashes that key and check entries,
// a verifying reader and an atomic writer (core/atomic_file.h). Header layout (docs/cache.md):
//
//   offset 0   8  magic, beginning with "DAISY" (core/cache_folder.h recognises entries by it)
//          8   4  format version (uint32)
//         12   4  the format's own 32-bit field (`detail`)
//         16  16  key: high 64 bits, then low 64 bits
//         32  16  the format's two 64-bit fields (`counts`: sizes of the payload's arrays)
//         48   8  payload checksum: XXH64, seed 0, of every byte from offset 64 to the end
//         56   8  header checksum: XXH64, seed 0, of bytes 0..55
//
// A file that fails any check is rejected with a one-line reason, never trusted.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/expected.h"
#include "core/memory.h"

namespace daisy {

// A 128-bit hash: the key of a cache entry.
struct Hash128 {
    uint64_t hi = 0, lo = 0;
    std::string hex() const;  // 32 lowercase hex digits, hi first; used as file names
    bool operator==(const Hash128&) const = default;
};

// 128-bit FNV-1a (Fowler, Noll, Vo; IETF draft-eastlake-fnv: offset basis
// 0x6c62272e07bb014262b821756295c58d, prime 2^88 + 0x13b), byte by byte.
class Fnv1a128 {
public:
    void update(std::span<const std::byte> bytes);
    void updateU64(uint64_t value);  // its 8 bytes, least significant first
    void updateText(std::string_view text);  // its length (updateU64), then its bytes
    Hash128 digest() const { return {hi_, lo_}; }

private:
    uint64_t hi_ = 0x6c62272e07bb0142ull, lo_ = 0x62b821756295c58dull;
};

// 64-bit FNV-1a (same source: offset basis 0xcbf29ce484222325, prime 2^40 + 0x1b3).
class Fnv1a64 {
public:
    void update(std::span<const std::byte> bytes);
    void update(std::string_view text) { update(std::as_bytes(std::span(text))); }
    uint64_t digest() const { return hash_; }

private:
    uint64_t hash_ = 0xcbf29ce484222325ull;
};

// XXH64 (Y. Collet, xxHash specification v0.8, doc/xxhash_spec.md in github.com/Cyan4973/
// xxHash), streaming: the same digest however the input is split. The files' checksums.
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

inline constexpr std::size_t kCacheHeaderBytes = 64;
inline constexpr std::size_t kCacheHeaderChecksummedBytes = 56;  // the header checksum's span
inline constexpr std::string_view kCacheMagicPrefix = "DAISY";
using CacheHeaderBytes = std::array<std::byte, kCacheHeaderBytes>;

// The header's fields (layout above); the header checksum is computed, not stored here.
struct CacheFileHeader {
    std::array<char, 8> magic{};
    uint32_t version = 0;
    uint32_t detail = 0;  // the format's own field (F: sizeof(FormFactorStats))
    Hash128 key;
    std::array<uint64_t, 2> counts{};  // the format's sizes (F: patch count, non-zeros)
    uint64_t payloadChecksum = 0;
};

CacheHeaderBytes encodeCacheHeader(const CacheFileHeader& header);  // with its checksum
CacheFileHeader decodeCacheHeader(const CacheHeaderBytes& bytes);
// True when bytes 56..63 are the XXH64 of bytes 0..55.
bool cacheHeaderChecksumMatches(const CacheHeaderBytes& bytes);

// What a reader expects of a file: its magic and version, and a description for messages.
struct CacheFileFormat {
    std::array<char, 8> magic{};
    uint32_t version = 0;
    std::string_view description;  // "form-factor cache file"
};

// Reads one entry: open() checks, in this order, that the file is a regular file, not empty,
// holds a whole header, and that the header's magic, version, checksum and key are the
// expected ones. The payload is then read in order through read()/readArray(), which keep a
// running XXH64; finish() compares it with the header's. Messages are one line without the
// path ("payload checksum mismatch (file corrupt)"); the caller names the file.
class CacheFileReader {
public:
    enum class Status { Missing, Rejected, Open };
    static CacheFileReader open(const std::filesystem::path& path, const CacheFileFormat& format,
                                const Hash128& key);

    Status status() const { return status_; }
    // Rejected: what is wrong. removable(): the file is known bad (false when it could not be
    // read at all, or is not a regular file: then it is not ours to delete).
    const std::string& problem() const { return problem_; }
    bool removable() const { return removable_; }
    const CacheFileHeader& header() const { return header_; }
    uint64_t fileBytes() const { return fileBytes_; }  // of the file opened (not of the path)

    // The next `bytes` of the payload; false (and finish() says truncated) when the file ends.
    bool read(void* data, std::size_t bytes);
    // `count` elements into `values`, on storage advised for huge pages (core/memory.h).
    template <typename T, typename Allocator>
    bool readArray(std::vector<T, Allocator>& values, uint64_t count) {
        resizeOnHugePages(values, count);
        return read(values.data(), count * sizeof(T));
    }
    // After the last read: "" when every read succeeded, the payload checksum matches and the
    // file has no bytes after the payload; otherwise the problem.
    std::string finish() const;

private:
    struct Closer {
        void operator()(std::FILE* file) const { std::fclose(file); }
    };
    Status status_ = Status::Missing;
    std::string problem_;
    bool removable_ = true;
    CacheFileHeader header_;
    uint64_t fileBytes_ = 0;
    uint64_t payloadRead_ = 0;
    bool truncated_ = false;
    std::unique_ptr<std::FILE, Closer> file_;
    std::unique_ptr<Xxh64> checksum_;
};

// The message of a rejected entry, "<path>: <what>; <then>" (then: what the caller does
// instead), after removing the file when `removeFile` (it is known bad).
std::string rejectCacheEntry(const std::filesystem::path& path, std::string_view what,
                             std::string_view then, bool removeFile);

// Bytes of an entry whose payload is `payload`.
uint64_t cacheFileBytes(std::span<const std::span<const std::byte>> payload);

// Writes header and payload (the spans in order) to `path` atomically (core/atomic_file.h); the
// payload checksum is computed here (header.payloadChecksum is ignored). The magic must begin
// with "DAISY". An Error names the path and the cause.
Expected<void> writeCacheFile(const std::filesystem::path& path, const CacheFileHeader& header,
                              std::span<const std::span<const std::byte>> payload);

// The bytes of one trivially copyable value, or of a vector's elements, for payload lists.
template <typename T>
std::span<const std::byte> bytesOf(const T& value) {
    return std::as_bytes(std::span<const T, 1>(&value, 1));
}
template <typename T, typename Allocator>
std::span<const std::byte> bytesOf(const std::vector<T, Allocator>& values) {
    return std::as_bytes(std::span<const T>(values));
}

}  // namespace daisy
