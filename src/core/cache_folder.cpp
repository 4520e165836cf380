#include "core/cache_folder.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "core/strings.h"

namespace daisy {
namespace {

int64_t nanosecondsOf(const timespec& time) {
    return int64_t{time.tv_sec} * 1'000'000'000 + time.tv_nsec;
}

int64_t nowNs() {
    timespec now{};
    clock_gettime(CLOCK_REALTIME, &now);
    return nanosecondsOf(now);
}

// Up to kCacheHeaderBytes of the file's start; the count read (0 when it cannot be read).
std::size_t readStart(const std::filesystem::path& path, CacheHeaderBytes& bytes) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0) return 0;
    std::size_t count = 0;
    while (count < bytes.size()) {
        const ssize_t got = ::read(fd, bytes.data() + count, bytes.size() - count);
        if (got <= 0) break;
        count += static_cast<std::size_t>(got);
    }
    ::close(fd);
    return count;
}

bool startsWithMagic(const CacheHeaderBytes& bytes, std::size_t count) {
    return count >= kCacheMagicPrefix.size() &&
        std::memcmp(bytes.data(), kCacheMagicPrefix.data(), kCacheMagicPrefix.size()) == 0;
}

// Removes `path`; true when it is gone (also when another process removed it first).
bool removeFile(const std::filesystem::path& path, CachePruneReport& report) {
    if (::unlink(path.c_str()) == 0 || errno == ENOENT) return true;
    report.failures.push_back(concat(path.string(), ": cannot remove: ", std::strerror(errno)));
    return false;
}

void removeStaleTemporaries(const CacheFolderListing& listing, CachePruneReport& report) {
    for (const CacheTemporary& temporary : listing.temporaries) {
        if (!temporary.stale) {
            ++report.liveTemporaries;
        } else if (removeFile(temporary.path, report)) {
            ++report.temporariesRemoved;
            report.temporaryBytes += temporary.bytes;
        }
    }
}

}  // namespace

CacheFolderListing listCacheFolder(const std::filesystem::path& directory) {
    CacheFolderListing listing;
    std::error_code error;
    std::filesystem::directory_iterator it(directory, error);
    if (error) return listing;
    const int64_t now = nowNs();
    const int64_t staleAgeNs =
        std::chrono::duration_cast<std::chrono::nanoseconds>(kStaleTemporaryAge).count();
    for (; it != std::filesystem::directory_iterator(); it.increment(error)) {
        if (error) break;
        const std::filesystem::path& path = it->path();
        struct stat info;
        if (::lstat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) continue;
        CacheHeaderBytes start{};
        const std::size_t count = readStart(path, start);
        const uint64_t bytes = static_cast<uint64_t>(info.st_size);
        const int64_t modifiedNs = nanosecondsOf(info.st_mtim);
        if (const int pid = temporaryWriterPid(path.filename().string()); pid > 0) {
            // A writer killed early may leave its temporary empty (stdio had not flushed).
            if (count >= kCacheMagicPrefix.size() && !startsWithMagic(start, count)) continue;
            const bool stale = !processIsAlive(pid) || now - modifiedNs > staleAgeNs;
            listing.temporaries.push_back({path, bytes, pid, stale});
            continue;
        }
        if (!startsWithMagic(start, count)) continue;
        CacheEntry entry;
        entry.path = path;
        entry.bytes = bytes;
        entry.lastUseNs = modifiedNs;
        entry.headerValid = count == kCacheHeaderBytes && cacheHeaderChecksumMatches(start);
        if (entry.headerValid) entry.header = decodeCacheHeader(start);
        listing.entryBytes += bytes;
        listing.entries.push_back(std::move(entry));
    }
    std::sort(listing.entries.begin(), listing.entries.end(),
              [](const CacheEntry& a, const CacheEntry& b) {
                  return a.lastUseNs != b.lastUseNs ? a.lastUseNs > b.lastUseNs
                                                    : a.path.filename() < b.path.filename();
              });
    return listing;
}

void markCacheEntryUsed(const std::filesystem::path& path) {
    const timespec times[2] = {{0, UTIME_NOW}, {0, UTIME_NOW}};  // access, modification
    ::utimensat(AT_FDCWD, path.c_str(), times, 0);
}

uint64_t defaultCacheSizeLimit(const std::filesystem::path& directory) {
    std::filesystem::path existing = directory.empty() ? "." : directory;
    std::error_code error;
    while (!std::filesystem::exists(existing, error) && existing.has_relative_path()) {
        existing = existing.parent_path();
    }
    const std::filesystem::space_info space = std::filesystem::space(existing, error);
    if (error || space.available == static_cast<std::uintmax_t>(-1)) {
        return kDefaultCacheSizeCapBytes;
    }
    return std::min<uint64_t>(kDefaultCacheSizeCapBytes, space.available / 10);
}

CachePruneReport pruneCacheFolder(const std::filesystem::path& directory, uint64_t limitBytes,
                                  const std::filesystem::path& keep) {
    CachePruneReport report;
    const CacheFolderListing listing = listCacheFolder(directory);
    removeStaleTemporaries(listing, report);
    uint64_t total = listing.entryBytes;
    int left = static_cast<int>(listing.entries.size());
    // Oldest first: the listing is most recently used first.
    for (auto it = listing.entries.rbegin(); it != listing.entries.rend() && total > limitBytes;
         ++it) {
        if (!keep.empty() && it->path.filename() == keep.filename()) continue;
        if (!removeFile(it->path, report)) continue;
        ++report.evicted;
        report.evictedBytes += it->bytes;
        total -= it->bytes;
        --left;
    }
    report.entriesLeft = left;
    report.bytesLeft = total;
    return report;
}

CachePruneReport clearCacheFolder(const std::filesystem::path& directory) {
    CachePruneReport report;
    const CacheFolderListing listing = listCacheFolder(directory);
    removeStaleTemporaries(listing, report);
    uint64_t total = listing.entryBytes;
    int left = static_cast<int>(listing.entries.size());
    for (const CacheEntry& entry : listing.entries) {
        if (!removeFile(entry.path, report)) continue;
        ++report.evicted;
        report.evictedBytes += entry.bytes;
        total -= entry.bytes;
        --left;
    }
    report.entriesLeft = left;
    report.bytesLeft = total;
    return report;
}

}  // namespace daisy
