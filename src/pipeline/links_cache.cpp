#include "pipeline/links_cache.h"

#include <system_error>
#include <type_traits>
#include <utility>

#include "core/cache_folder.h"
#include "core/strings.h"
#include "pipeline/solution_cache.h"

namespace daisy {

namespace {

// The payload's first bytes: the sizes of its arrays and the build's statistics.
struct LinksLayout {
    uint64_t nodes = 0;
    uint64_t patches = 0;
    uint64_t nearEntries = 0;
    uint64_t planarHalfLinks = 0;
    uint64_t otherHalfLinks = 0;
    LinkStats stats;
};

static_assert(std::is_trivially_copyable_v<LinksLayout>, "the layout is stored as raw bytes");
static_assert(std::is_trivially_copyable_v<HierarchyNode>, "nodes are stored as raw bytes");
static_assert(std::is_trivially_copyable_v<FarHalfLinks::OtherLink>,
              "far links are stored as raw bytes");

const CacheFileFormat kFormat{
    {'D', 'A', 'I', 'S', 'Y', 'H', '\0', '\0'}, kLinksCacheVersion, "links cache file"};

// Bytes of the payload's arrays after the layout, in their order (the tree's nodes, order and
// leaves; the near factors' offsets, columns and values; the far half-links' offsets, slots
// and weights between planar nodes, and the others' offsets and links; the far scales, row
// sums and exposed shares); false when the sizes cannot be a transport's (a corrupt file).
bool arrayBytes(const LinksLayout& layout, uint64_t& bytes) {
    const uint64_t n = layout.patches, nodes = layout.nodes;
    if (n > UINT32_MAX || nodes != (n > 0 ? 2 * n - 1 : 0) || layout.nearEntries > (1ull << 40) ||
        layout.planarHalfLinks > (1ull << 40) || layout.otherHalfLinks > (1ull << 40)) {
        return false;
    }
    bytes = nodes * sizeof(HierarchyNode) + 2 * n * sizeof(uint32_t) + (n + 1) * sizeof(uint64_t) +
        layout.nearEntries * (sizeof(uint32_t) + sizeof(float)) +
        2 * (nodes + 1) * sizeof(uint64_t) +
        layout.planarHalfLinks * (sizeof(uint32_t) + sizeof(float)) +
        layout.otherHalfLinks * sizeof(FarHalfLinks::OtherLink) + 2 * n * sizeof(double) +
        n * sizeof(float);
    return true;
}

}  // namespace

LinksKey linksKey(const FormFactorKey& formFactors, const RadiositySystem& system) {
    Fnv1a128 hash;
    hash.updateU64(kLinksCacheVersion);
    hash.updateU64(formFactors.hi);
    hash.updateU64(formFactors.lo);
    hashRadiositySystem(hash, system);
    return hash.digest();
}

LinksCache::LinksCache(std::filesystem::path directory, uint64_t sizeLimitBytes)
    : directory_(std::move(directory)), sizeLimitBytes_(sizeLimitBytes) {}

std::filesystem::path LinksCache::entryPath(const LinksKey& key) const {
    return directory_ / (key.hex() + ".dhl");
}

std::string LinksCache::describe(const CacheFileHeader& header) {
    if (header.magic != kFormat.magic) return {};
    std::string text = concat("links: ", formatCount(header.counts[0]), " patches, ",
                              formatCount(header.counts[1]), " far half-links (hierarchical)");
    if (header.version != kLinksCacheVersion) {
        text += concat(" (format version ", header.version, ", this build reads ",
                       kLinksCacheVersion, ")");
    }
    return text;
}

LinksLookup LinksCache::load(const LinksKey& key, const PatchMesh& mesh,
                             uint64_t maxMemoryBytes) const {
    const std::filesystem::path path = entryPath(key);
    const auto reject = [&](const std::string& what, bool removeFile = true) {
        LinksLookup rejected;
        rejected.status = LinksLookup::Status::Rejected;
        rejected.message = rejectCacheEntry(path, what, "building the links", removeFile);
        return rejected;
    };
    CacheFileReader reader = CacheFileReader::open(path, kFormat, key);
    if (reader.status() == CacheFileReader::Status::Missing) return {};
    if (reader.status() == CacheFileReader::Status::Rejected) {
        return reject(reader.problem(), reader.removable());
    }
    const CacheFileHeader& header = reader.header();
    if (header.detail != sizeof(HierarchyNode)) {
        return reject(concat("tree nodes of ", header.detail, " bytes, this build's are ",
                             sizeof(HierarchyNode), " (written by a different build)"));
    }
    LinksLayout layout;
    if (!reader.read(&layout, sizeof(layout))) return reject(reader.finish());
    uint64_t bytes = 0;
    if (!arrayBytes(layout, bytes) || layout.patches != header.counts[0] ||
        layout.planarHalfLinks + layout.otherHalfLinks != header.counts[1]) {
        return reject("sizes out of range (file corrupt)");
    }
    // The key covers the patches: another count is a damaged file.
    if (layout.patches != mesh.patchCount()) {
        return reject(concat(layout.patches, " patches, the scene's are ", mesh.patchCount(),
                             " (file corrupt)"));
    }
    if (reader.fileBytes() != kCacheHeaderBytes + sizeof(LinksLayout) + bytes) {
        return reject(concat("file is ", reader.fileBytes(), " bytes, its header says ",
                             kCacheHeaderBytes + sizeof(LinksLayout) + bytes,
                             " (truncated or damaged)"));
    }
    if (bytes > maxMemoryBytes) {
        return reject(concat("its links need ", formatBytes(double(bytes)),
                             ", more than --max-memory ", formatBytes(double(maxMemoryBytes))),
                      false);
    }
    const uint64_t n = layout.patches;
    HierarchicalParts parts;
    SparseMatrix& near = parts.near;
    FarHalfLinks& far = parts.far;
    near.size = uint32_t(n);
    const bool read = reader.readArray(parts.tree.nodes, layout.nodes) &&
        reader.readArray(parts.tree.order, n) && reader.readArray(parts.tree.leafOf, n) &&
        reader.readArray(near.rowOffsets, n + 1) &&
        reader.readArray(near.columns, layout.nearEntries) &&
        reader.readArray(near.values, layout.nearEntries) &&
        reader.readArray(far.planarOffsets, layout.nodes + 1) &&
        reader.readArray(far.planarSlots, layout.planarHalfLinks) &&
        reader.readArray(far.planarWeights, layout.planarHalfLinks) &&
        reader.readArray(far.otherOffsets, layout.nodes + 1) &&
        reader.readArray(far.others, layout.otherHalfLinks) &&
        reader.readArray(parts.farScale, n) && reader.readArray(parts.rowSums, n) &&
        reader.readArray(parts.exposure, n);
    if (!read) return reject(reader.finish());
    if (std::string problem = reader.finish(); !problem.empty()) return reject(problem);
    parts.stats = layout.stats;
    auto transport = std::make_shared<const HierarchicalTransport>(mesh, std::move(parts));
    if (std::string problem = transport->checkStructure(); !problem.empty()) {
        return reject(concat(problem, " (file corrupt)"));
    }
    markCacheEntryUsed(path);
    LinksLookup lookup;
    lookup.status = LinksLookup::Status::Hit;
    lookup.transport = std::move(transport);
    return lookup;
}

std::string LinksCache::store(const LinksKey& key, const HierarchicalTransport& transport) const {
    std::error_code error;
    std::filesystem::create_directories(directory_, error);
    if (error) {
        return concat("links not cached: cannot create the cache folder ", directory_.string(),
                      ": ", error.message());
    }
    const ClusterTree& tree = transport.tree();
    const SparseMatrix& near = transport.near();
    const FarHalfLinks& far = transport.farLinks();
    LinksLayout layout;
    layout.nodes = tree.nodes.size();
    layout.patches = near.size;
    layout.nearEntries = near.nonzeroCount();
    layout.planarHalfLinks = far.planarSlots.size();
    layout.otherHalfLinks = far.others.size();
    layout.stats = transport.linkStats();
    CacheFileHeader header;
    header.magic = kFormat.magic;
    header.version = kFormat.version;
    header.detail = sizeof(HierarchyNode);
    header.key = key;
    header.counts = {layout.patches, far.count()};
    const std::span<const std::byte> payload[] = {bytesOf(layout),
                                                  bytesOf(tree.nodes),
                                                  bytesOf(tree.order),
                                                  bytesOf(tree.leafOf),
                                                  bytesOf(near.rowOffsets),
                                                  bytesOf(near.columns),
                                                  bytesOf(near.values),
                                                  bytesOf(far.planarOffsets),
                                                  bytesOf(far.planarSlots),
                                                  bytesOf(far.planarWeights),
                                                  bytesOf(far.otherOffsets),
                                                  bytesOf(far.others),
                                                  bytesOf(transport.farScale()),
                                                  std::as_bytes(transport.rowSums()),
                                                  bytesOf(transport.exposure())};
    const uint64_t limit =
        sizeLimitBytes_ != 0 ? sizeLimitBytes_ : defaultCacheSizeLimit(directory_);
    const uint64_t entryBytes = cacheFileBytes(payload);
    if (entryBytes > limit) {
        return concat("links not cached: their entry of ", formatBytes(double(entryBytes)),
                      " is over the cache size limit of ", formatBytes(double(limit)),
                      " (--cache-size)");
    }
    const std::filesystem::path path = entryPath(key);
    if (auto written = writeCacheFile(path, header, payload); !written) {
        return concat("links not cached: ", written.error().message);
    }
    pruneCacheFolder(directory_, limit, path);
    return {};
}

}  // namespace daisy
