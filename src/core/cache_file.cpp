#include "core/cache_file.h"

#include <sys/stat.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>

#include "core/atomic_file.h"
#include "core/check.h"
#include "core/strings.h"

namespace daisy {

// Headers and payload arrays are written and read as the host's bytes; the format is
// little-endian.
static_assert(std::endian::native == std::endian::little, "cache files are little-endian");

namespace {

// XXH64 constants and steps (xxHash specification v0.8, section "XXH64 algorithm").
constexpr uint64_t kPrime1 = 0x9E3779B185EBCA87ull;
constexpr uint64_t kPrime2 = 0xC2B2AE3D27D4EB4Full;
constexpr uint64_t kPrime3 = 0x165667B19E3779F9ull;
constexpr uint64_t kPrime4 = 0x85EBCA77C2B2AE63ull;
constexpr uint64_t kPrime5 = 0x27D4EB2F165667C5ull;

uint64_t xxhRound(uint64_t accumulator, uint64_t lane) {
    return std::rotl(accumulator + lane * kPrime2, 31) * kPrime1;
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

uint64_t headerChecksum(const CacheHeaderBytes& bytes) {
    return xxh64(std::span(bytes.data(), kCacheHeaderChecksummedBytes));
}

}  // namespace

std::string Hash128::hex() const {
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

void Fnv1a128::updateText(std::string_view text) {
    updateU64(text.size());
    update(std::as_bytes(std::span(text.data(), text.size())));
}

void Fnv1a64::update(std::span<const std::byte> bytes) {
    for (std::byte b : bytes)
        hash_ = (hash_ ^ std::to_integer<uint64_t>(b)) * 0x100000001b3ull;
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
        acc = std::rotl(lanes_[0], 1) + std::rotl(lanes_[1], 7) + std::rotl(lanes_[2], 12) +
            std::rotl(lanes_[3], 18);
        for (uint64_t lane : lanes_)
            acc = xxhMerge(acc, lane);
    } else {
        acc = seed_ + kPrime5;
    }
    acc += totalBytes_;
    const std::byte* p = buffer_;
    std::size_t left = buffered_;
    for (; left >= 8; p += 8, left -= 8)
        acc = std::rotl(acc ^ xxhRound(0, readU64(p)), 27) * kPrime1 + kPrime4;
    if (left >= 4) {
        acc = std::rotl(acc ^ (uint64_t(readU32(p)) * kPrime1), 23) * kPrime2 + kPrime3;
        p += 4;
        left -= 4;
    }
    for (; left > 0; ++p, --left)
        acc = std::rotl(acc ^ (std::to_integer<uint64_t>(*p) * kPrime5), 11) * kPrime1;
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

CacheHeaderBytes encodeCacheHeader(const CacheFileHeader& header) {
    CacheHeaderBytes bytes{};
    std::memcpy(bytes.data() + 0, header.magic.data(), 8);
    std::memcpy(bytes.data() + 8, &header.version, 4);
    std::memcpy(bytes.data() + 12, &header.detail, 4);
    std::memcpy(bytes.data() + 16, &header.key.hi, 8);
    std::memcpy(bytes.data() + 24, &header.key.lo, 8);
    std::memcpy(bytes.data() + 32, &header.counts[0], 8);
    std::memcpy(bytes.data() + 40, &header.counts[1], 8);
    std::memcpy(bytes.data() + 48, &header.payloadChecksum, 8);
    const uint64_t checksum = headerChecksum(bytes);
    std::memcpy(bytes.data() + 56, &checksum, 8);
    return bytes;
}

CacheFileHeader decodeCacheHeader(const CacheHeaderBytes& bytes) {
    CacheFileHeader header;
    std::memcpy(header.magic.data(), bytes.data(), 8);
    header.version = readU32(bytes.data() + 8);
    header.detail = readU32(bytes.data() + 12);
    header.key.hi = readU64(bytes.data() + 16);
    header.key.lo = readU64(bytes.data() + 24);
    header.counts[0] = readU64(bytes.data() + 32);
    header.counts[1] = readU64(bytes.data() + 40);
    header.payloadChecksum = readU64(bytes.data() + 48);
    return header;
}

bool cacheHeaderChecksumMatches(const CacheHeaderBytes& bytes) {
    return headerChecksum(bytes) == readU64(bytes.data() + kCacheHeaderChecksummedBytes);
}

CacheFileReader CacheFileReader::open(const std::filesystem::path& path,
                                      const CacheFileFormat& format, const Hash128& key) {
    CacheFileReader reader;
    const auto reject = [&reader](std::string problem, bool removable = true) {
        reader.status_ = Status::Rejected;
        reader.problem_ = std::move(problem);
        reader.removable_ = removable;
        reader.file_.reset();
        return std::move(reader);
    };
    reader.file_.reset(std::fopen(path.c_str(), "rb"));
    if (!reader.file_ && (errno == ENOENT || errno == ENOTDIR)) return reader;  // Missing
    if (!reader.file_) return reject(concat("cannot read: ", std::strerror(errno)), false);
    // The size of the file opened, not of the path: a concurrent store may rename over it.
    struct stat info;
    if (fstat(fileno(reader.file_.get()), &info) != 0) {
        return reject(concat("cannot read: ", std::strerror(errno)), false);
    }
    if (!S_ISREG(info.st_mode)) return reject("not a regular file", false);
    reader.fileBytes_ = static_cast<uint64_t>(info.st_size);
    if (reader.fileBytes_ == 0) return reject("empty file");
    if (reader.fileBytes_ < kCacheHeaderBytes) {
        return reject(
            concat("truncated header (", reader.fileBytes_, " of ", kCacheHeaderBytes, " bytes)"));
    }
    CacheHeaderBytes bytes;
    if (std::fread(bytes.data(), 1, bytes.size(), reader.file_.get()) != bytes.size()) {
        return reject("cannot read the header");
    }
    reader.header_ = decodeCacheHeader(bytes);
    // In the order that gives the most useful message (a future version may move the
    // checksum, so the version comes before it).
    if (reader.header_.magic != format.magic) {
        return reject(concat("not a DaisyRiot ", format.description, " (bad magic)"));
    }
    if (reader.header_.version != format.version) {
        return reject(concat("format version ", reader.header_.version,
                             ", this build reads version ", format.version));
    }
    if (!cacheHeaderChecksumMatches(bytes))
        return reject("header checksum mismatch (file corrupt)");
    if (reader.header_.key != key) {
        return reject(concat("holds the entry for key ", reader.header_.key.hex(), ", not ",
                             key.hex(), " (renamed or copied file)"));
    }
    reader.status_ = Status::Open;
    reader.checksum_ = std::make_unique<Xxh64>();
    return reader;
}

bool CacheFileReader::read(void* data, std::size_t bytes) {
    DAISY_CHECK(status_ == Status::Open);
    if (truncated_) return false;
    if (bytes == 0) return true;
    if (std::fread(data, 1, bytes, file_.get()) != bytes) {
        truncated_ = true;
        return false;
    }
    checksum_->update(std::span(static_cast<const std::byte*>(data), bytes));
    payloadRead_ += bytes;
    return true;
}

std::string CacheFileReader::finish() const {
    DAISY_CHECK(status_ == Status::Open);
    if (truncated_) return "file ended early while reading (truncated)";
    if (checksum_->digest() != header_.payloadChecksum) {
        return "payload checksum mismatch (file corrupt)";
    }
    const uint64_t read = kCacheHeaderBytes + payloadRead_;
    if (read != fileBytes_) {
        return concat("file is ", fileBytes_, " bytes, its payload ends at ", read, " (damaged)");
    }
    return {};
}

uint64_t cacheFileBytes(std::span<const std::span<const std::byte>> payload) {
    uint64_t bytes = kCacheHeaderBytes;
    for (const auto& part : payload)
        bytes += part.size();
    return bytes;
}

Expected<void> writeCacheFile(const std::filesystem::path& path, const CacheFileHeader& header,
                              std::span<const std::span<const std::byte>> payload) {
    DAISY_CHECK(std::string_view(header.magic.data(), kCacheMagicPrefix.size()) ==
                kCacheMagicPrefix);
    CacheFileHeader complete = header;
    Xxh64 checksum;
    for (const auto& part : payload)
        checksum.update(part);
    complete.payloadChecksum = checksum.digest();
    const CacheHeaderBytes headerBytes = encodeCacheHeader(complete);
    const auto put = [](std::FILE* file, std::span<const std::byte> bytes) {
        return bytes.empty() || std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
    };
    return writeFileAtomically(path.string(), [&](std::FILE* file) {
        bool ok = put(file, headerBytes);
        for (const auto& part : payload)
            ok = ok && put(file, part);
        return ok ? std::string() : concat("write failed: ", std::strerror(errno));
    });
}

std::string rejectCacheEntry(const std::filesystem::path& path, std::string_view what,
                             std::string_view then, bool removeFile) {
    if (removeFile) {
        std::error_code ignored;
        std::filesystem::remove(path, ignored);
    }
    return concat(path.string(), ": ", what, "; ", then);
}

}  // namespace daisy
