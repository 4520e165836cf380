#pragma once
// Disk cache of the hierarchical transport (docs/cache.md, "Links"), beside F's entries in the
// same folder: the cluster tree, the near and far links and the row caps' scales of a built
// HierarchicalTransport, so that a second render or view of a scene skips the links' build.
// An entry is one file "<key hex>.dhl" in the layout of core/cache_file.h (magic "DAISYH",
// detail = sizeof(HierarchyNode), counts = patch count and far half-link count), its payload
// LinksLayout, then the arrays in its order. Every entry is fully verified on load (sizes,
// checksum, the restored transport's checkStructure) and rejected (then removed) when a check
// fails; written atomically; the folder's size limit and eviction are F's (core/cache_folder.h).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "core/cache_file.h"
#include "hierarchical/hierarchical_transport.h"
#include "pipeline/formfactor_cache.h"
#include "radiosity/radiosity_system.h"

namespace daisy {

// Bump when the key's byte stream, the file layout, HierarchyNode, FarHalfLinks or LinkStats
// change, or the rules that make the links or the exposed parts they are sampled on
// (radiosity/patch_exposure.h): an entry would give other links than a build.
inline constexpr uint32_t kLinksCacheVersion = 9;

using LinksKey = Hash128;

// Hash (128-bit FNV-1a, as F's key) of: kLinksCacheVersion; F's key (the patches, the
// form-factor settings, the backend family and the hierarchy settings); what the oracle weighs:
// the wavelength samples and bin widths, E, the areas, every patch's operator index and every
// operator's re-radiation matrix.
LinksKey linksKey(const FormFactorKey& formFactors, const RadiositySystem& system);

struct LinksLookup {
    enum class Status { Hit, Miss, Rejected };
    Status status = Status::Miss;
    std::shared_ptr<const HierarchicalTransport> transport;  // on Hit
    std::string message;  // on Rejected: one line naming the file and what is wrong
};

class LinksCache {
public:
    // `sizeLimitBytes`: as FormFactorCache's (0 = the folder's default).
    explicit LinksCache(std::filesystem::path directory, uint64_t sizeLimitBytes = 0);
    std::filesystem::path entryPath(const LinksKey& key) const;  // directory / "<hex>.dhl"
    // Reads, verifies and restores an entry for `mesh`'s patches; refuses one whose arrays
    // would pass `maxMemoryBytes`. A file that fails is Rejected and removed. A hit marks the
    // entry as used now.
    LinksLookup load(const LinksKey& key, const PatchMesh& mesh, uint64_t maxMemoryBytes) const;
    // Writes the entry atomically and keeps the folder under its size limit. A failure is a
    // one-line warning ("links not cached: ..."), "" on success.
    std::string store(const LinksKey& key, const HierarchicalTransport& transport) const;

    // A one-line summary for `daisy cache list`, or "" when the header is not a links entry's.
    static std::string describe(const CacheFileHeader& header);

private:
    std::filesystem::path directory_;
    uint64_t sizeLimitBytes_ = 0;
};

}  // namespace daisy
