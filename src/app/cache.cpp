// `daisy cache list|clear|prune`: the disk cache's folder as a whole (docs/cache.md): what it
// holds, emptying it, and evicting to the size limit. The folder is the one render, solve and
// the other commands use: --cache DIR, else $XDG_CACHE_HOME/daisyriot or ~/.cache/daisyriot.
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>
#include <string>

#include "app/commands.h"
#include "core/cache_folder.h"
#include "core/log.h"
#include "core/strings.h"
#include "pipeline/formfactor_cache.h"
#include "pipeline/links_cache.h"
#include "pipeline/solution_cache.h"

namespace daisy::app {
namespace {

// "2026-12-03 19:40:12", local time.
std::string formatLastUse(int64_t unixNs) {
    const std::time_t seconds = static_cast<std::time_t>(unixNs / 1'000'000'000);
    std::tm local{};
    localtime_r(&seconds, &local);
    char text[32];
    std::strftime(text, sizeof(text), "%Y-%m-%d %H:%M:%S", &local);
    return text;
}

// What an entry holds, from its header.
std::string summaryOf(const CacheEntry& entry) {
    if (!entry.headerValid) return "damaged header (rejected and removed when next read)";
    if (std::string text = FormFactorCache::describe(entry.header); !text.empty()) return text;
    if (std::string text = SolutionCache::describe(entry.header); !text.empty()) return text;
    if (std::string text = LinksCache::describe(entry.header); !text.empty()) return text;
    std::string magic;
    for (char c : entry.header.magic)
        if (c >= ' ' && c <= '~') magic += c;
    return concat(magic, " entry, format version ", entry.header.version, ", key ",
                  entry.header.key.hex());
}

// "1 entry", "3 entries", "2 temporary files".
std::string plural(uint64_t count, const std::string& noun) {
    if (count == 1) return concat("1 ", noun);
    if (noun.ends_with("y"))
        return concat(formatCount(count), " ", noun.substr(0, noun.size() - 1), "ies");
    return concat(formatCount(count), " ", noun, "s");
}

struct Limit {
    uint64_t bytes = 0;
    std::string text;  // "4 GiB (the default)"
};

Limit limitOf(const CacheOptions& options, const std::filesystem::path& folder) {
    Limit limit;
    if (!options.cacheSizeText.empty() && parseByteSize(options.cacheSizeText, limit.bytes)) {
        limit.text = concat(formatBytes(double(limit.bytes)), " (--cache-size)");
    } else {
        limit.bytes = defaultCacheSizeLimit(folder);
        limit.text = concat(formatBytes(double(limit.bytes)),
                            " (the default: a tenth of the free space, at most 4 GiB)");
    }
    return limit;
}

int list(const std::filesystem::path& folder, const Limit& limit) {
    const CacheFolderListing listing = listCacheFolder(folder);
    std::printf("cache folder %s\n", folder.string().c_str());
    if (!listing.entries.empty()) {
        std::printf("  %-19s  %10s  %-36s  %s\n", "last use", "size", "entry", "holds");
    }
    for (const CacheEntry& entry : listing.entries) {
        std::printf("  %-19s  %10s  %-36s  %s\n", formatLastUse(entry.lastUseNs).c_str(),
                    formatBytes(double(entry.bytes)).c_str(),
                    entry.path.filename().string().c_str(), summaryOf(entry).c_str());
    }
    for (const CacheTemporary& temporary : listing.temporaries) {
        std::printf("  temporary %s, %s: %s\n", temporary.path.filename().string().c_str(),
                    formatBytes(double(temporary.bytes)).c_str(),
                    temporary.stale ? "stale (its writer is gone; removed by the next store or "
                                      "prune)"
                                    : "being written by a running process");
    }
    std::printf("%s, %s; limit %s\n", plural(listing.entries.size(), "entry").c_str(),
                formatBytes(double(listing.entryBytes)).c_str(), limit.text.c_str());
    return 0;
}

// The lines common to clear and prune; 1 when a file could not be removed.
int finish(const CachePruneReport& report, const char* verb) {
    std::printf("%s %s (%s)", verb, plural(uint64_t(report.evicted), "entry").c_str(),
                formatBytes(double(report.evictedBytes)).c_str());
    if (report.temporariesRemoved > 0) {
        std::printf(", removed %s of dead writers (%s)",
                    plural(uint64_t(report.temporariesRemoved), "temporary file").c_str(),
                    formatBytes(double(report.temporaryBytes)).c_str());
    }
    std::printf("; %s left (%s)", plural(uint64_t(report.entriesLeft), "entry").c_str(),
                formatBytes(double(report.bytesLeft)).c_str());
    if (report.liveTemporaries > 0) {
        std::printf("; %s of running writers kept",
                    plural(uint64_t(report.liveTemporaries), "temporary file").c_str());
    }
    std::printf("\n");
    for (const std::string& failure : report.failures)
        logError(failure);
    return report.failures.empty() ? 0 : 1;
}

CLI::App* addCacheOptions(CLI::App& app, CacheOptions& options) {
    auto* command = app.add_subcommand(
        "cache",
        "List, clear or prune the disk cache of F and solutions (least recently used first)");
    command
        ->add_option("ACTION", options.action,
                     "list (entries, sizes, last use), clear (remove every entry) or prune "
                     "(evict to the size limit, remove temporaries of dead writers)")
        ->check(CLI::IsMember({"list", "clear", "prune"}))
        ->required();
    command->add_option("--cache", options.cacheDir,
                        "Directory of the form-factor cache (default: $XDG_CACHE_HOME/daisyriot)");
    addCacheSizeOption(*command, options.cacheSizeText);
    return command;
}

int runCache(const CacheOptions& options) {
    const std::filesystem::path folder = options.cacheDir.empty()
        ? FormFactorCache::defaultDirectory()
        : std::filesystem::path(options.cacheDir);
    if (folder.empty()) {
        logError(
            "daisy cache: no cache folder: HOME and XDG_CACHE_HOME are unset or relative "
            "(give --cache DIR)");
        return 2;
    }
    std::error_code error;
    if (std::filesystem::exists(folder, error) && !std::filesystem::is_directory(folder, error)) {
        logError(concat(folder.string(), ": not a folder (--cache takes the cache's folder)"));
        return 2;
    }
    const Limit limit = limitOf(options, folder);
    if (options.action == "list") return list(folder, limit);
    if (options.action == "clear") {
        std::printf("cache folder %s: ", folder.string().c_str());
        return finish(clearCacheFolder(folder), "removed");
    }
    std::printf("cache folder %s, limit %s: ", folder.string().c_str(), limit.text.c_str());
    return finish(pruneCacheFolder(folder, limit.bytes), "evicted");
}

}  // namespace

void addCacheCommand(CLI::App& app, CommandContext& context) {
    auto options = std::make_shared<CacheOptions>();
    CLI::App* command = addCacheOptions(app, *options);
    context.onRun(command, [options]() -> Expected<int> { return runCache(*options); });
}

}  // namespace daisy::app
