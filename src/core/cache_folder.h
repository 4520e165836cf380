#pragma once
// A disk-cache folder as a whole (docs/cache.md, "Size limit and eviction"): its entries, its
// size limit with least-recently-used eviction, and the temporaries writers left behind.
//
// An entry is a regular file of the folder whose first bytes are a cache-file magic ("DAISY",
// core/cache_file.h), whatever its name; other files are never touched, so a folder shared with
// other data is safe. Its last use is its modification time: set by the write, and by every hit
// (markCacheEntryUsed). Keeping recency in the files themselves, not in an index, leaves nothing
// for concurrent processes to corrupt: each sees the folder as it is, and a file another process
// removed first is skipped.
//
// A temporary is "<name>.tmp-<pid>" (core/atomic_file.h) holding the start of an entry (or
// fewer than 5 bytes). It is stale when no process <pid> is alive or it is older than
// kStaleTemporaryAge (a pid reused by another process, or a writer in another pid namespace).
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/atomic_file.h"
#include "core/cache_file.h"

namespace daisy {

inline constexpr uint64_t kDefaultCacheSizeCapBytes = uint64_t{4} << 30;  // 4 GiB
inline constexpr std::chrono::hours kStaleTemporaryAge{24};

struct CacheEntry {
    std::filesystem::path path;
    uint64_t bytes = 0;
    int64_t lastUseNs = 0;  // modification time, nanoseconds since the Unix epoch
    bool headerValid = false;  // the header's checksum matches (else `header` is unreliable)
    CacheFileHeader header;
};

struct CacheTemporary {
    std::filesystem::path path;
    uint64_t bytes = 0;
    int pid = 0;  // the writer's process id, from the name
    bool stale = false;  // the writer is dead, or the file is older than kStaleTemporaryAge
};

struct CacheFolderListing {
    std::vector<CacheEntry> entries;  // most recently used first
    std::vector<CacheTemporary> temporaries;
    uint64_t entryBytes = 0;  // the entries' total
};

// What is in `directory` now; an absent folder is an empty listing.
CacheFolderListing listCacheFolder(const std::filesystem::path& directory);

// Records a use of the entry at `path`: its modification time becomes now. Best effort (a
// read-only folder keeps the old time; the entry is then evicted earlier, never wrongly read).
void markCacheEntryUsed(const std::filesystem::path& path);

// The default size limit of a cache in `directory`: the smaller of kDefaultCacheSizeCapBytes and
// a tenth of the space available on its file system (of its nearest existing ancestor when it
// does not exist yet); kDefaultCacheSizeCapBytes when that is unknown.
uint64_t defaultCacheSizeLimit(const std::filesystem::path& directory);

struct CachePruneReport {
    int evicted = 0;  // entries removed
    uint64_t evictedBytes = 0;
    int temporariesRemoved = 0;
    uint64_t temporaryBytes = 0;
    int entriesLeft = 0;
    uint64_t bytesLeft = 0;  // the entries' total afterwards
    int liveTemporaries = 0;  // temporaries of running writers, kept
    std::vector<std::string> failures;  // one line per file that could not be removed
};

// Removes the stale temporaries, then the least recently used entries (oldest modification time
// first, ties by name) until the entries total at most `limitBytes`. The entry at `keep` (the
// one just written; empty = none) is never evicted, even when it alone is over the limit.
CachePruneReport pruneCacheFolder(const std::filesystem::path& directory, uint64_t limitBytes,
                                  const std::filesystem::path& keep = {});

// Removes every entry and every stale temporary; a running writer's temporary is kept.
CachePruneReport clearCacheFolder(const std::filesystem::path& directory);

}  // namespace daisy
