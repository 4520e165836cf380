#pragma once
// Disk cache of converged solutions (docs/cache.md, "Solutions"), beside F's entries in the same
// folder: the radiosity B and the gathered light G of a converged solve, so that a warm
// `daisy view` shows the converged picture without solving and `render` / `solve` skip the solve.
// An entry is one file "<key hex>.dbr" in the layout of core/cache_file.h (magic "DAISYB",
// detail = sizeof(SolutionStats), counts = patch count and wavelength count), its payload the
// SolutionStats bytes, B, then G (patches x wavelengths doubles each; G absent when
// stats.hasGathered is 0). Every entry is fully verified on load and rejected (then removed)
// when a check fails; written atomically; the folder's size limit and eviction are F's
// (core/cache_folder.h).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/cache_file.h"
#include "pipeline/formfactor_cache.h"
#include "radiosity/radiosity_system.h"
#include "radiosity/solver.h"

namespace daisy {

// Bump when the key's byte stream, the file layout or SolutionStats change, or the rules of
// the patches' exposed parts (radiosity/patch_exposure.h), which the solve answers for.
inline constexpr uint32_t kSolutionCacheVersion = 2;

// 128-bit key of exactly what a converged B depends on (hex() names the file).
using SolutionKey = Hash128;

// Hash (128-bit FNV-1a, as F's key) of: kSolutionCacheVersion; F's key (the patches, the
// form-factor settings and the backend family: everything the transport and the patches'
// exposed parts depend on); the system as the solve uses it: the wavelength samples and bin
// widths, E (with the punctual lights' direct light), the areas, every patch's operator index
// and every operator's re-radiation matrix (the materials after textures, edits and
// --materials); the solver kind, tolerance and iteration limit. About 8 (m + 2) bytes a patch.
SolutionKey solutionKey(const FormFactorKey& formFactors, const RadiositySystem& system,
                        const SolverSettings& solver);

// The system's part of that key: the patch and wavelength counts, the samples and bin widths,
// E, the areas, every patch's operator index and every operator's re-radiation matrix (also
// what the hierarchical links' oracle weighs: pipeline/links_cache.h).
void hashRadiositySystem(Fnv1a128& hash, const RadiositySystem& system);

// Stored with B: what the solve that produced it reported.
struct SolutionStats {
    int32_t iterations = 0;
    uint32_t hasGathered = 0;  // 1: G follows B in the payload
    double residual = 0;  // true relative residual of the stored B
    double solveSeconds = 0;  // wall time of that solve
};

struct SolutionLookup {
    enum class Status { Hit, Miss, Rejected };
    Status status = Status::Miss;
    std::vector<double> radiosity;  // on Hit: B, patches x m
    std::vector<double> gathered;  // on Hit: G, patches x m, or empty
    SolutionStats stats;
    std::string message;  // on Rejected: one line naming the file and what is wrong
};

class SolutionCache {
public:
    // `sizeLimitBytes`: as FormFactorCache's (0 = the folder's default).
    explicit SolutionCache(std::filesystem::path directory, uint64_t sizeLimitBytes = 0);
    std::filesystem::path entryPath(const SolutionKey& key) const;  // directory / "<hex>.dbr"
    // Reads and verifies an entry for `patchCount` patches and `wavelengthCount` samples (magic,
    // version, key, sizes, checksum, finite values); a file that fails is Rejected and removed.
    // A hit marks the entry as used now.
    SolutionLookup load(const SolutionKey& key, uint64_t patchCount,
                        uint64_t wavelengthCount) const;
    // Writes the entry atomically and keeps the folder under its size limit; `gathered` may be
    // empty. A failure is a one-line warning ("B not cached: ..."), "" on success.
    std::string store(const SolutionKey& key, uint64_t patchCount, uint64_t wavelengthCount,
                      const std::vector<double>& radiosity, const std::vector<double>& gathered,
                      const SolutionStats& stats) const;

    // A one-line summary for `daisy cache list` ("B: 7,712 patches x 7 wavelengths"), or "" when
    // the header is not a solution entry's.
    static std::string describe(const CacheFileHeader& header);

private:
    std::filesystem::path directory_;
    uint64_t sizeLimitBytes_ = 0;
};

}  // namespace daisy
