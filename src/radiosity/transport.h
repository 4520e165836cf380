#pragma once
// How light moves between patches (DESIGN.md sections 1 and 2): the operator T in
//     B = E + M G,   G = T B,
// G_i the spectral irradiance gathered by patch i (W m^-2 nm^-1) from the radiosity B of every
// patch, both patchCount x m, row-major. Everything the front ends need from the transport goes
// through this interface (reached through the session, pipeline/session.h), so a representation
// other than the all-pairs matrix F (radiosity/matrix_transport.h) can take its place without
// touching them. Instances are immutable once built and safe to share across threads.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/expected.h"
#include "radiosity/matrix_compare.h"
#include "radiosity/radiosity_system.h"
#include "radiosity/solver.h"

namespace daisy {

// Sizes of a transport, for stage lines, `info` and the bench tables.
struct TransportStats {
    uint64_t entries = 0;  // stored factors: F's non-zeros
    uint64_t bytes = 0;  // memory held by the representation
};

// One factor of a patch's row: patch i receives the fraction `factor` of j's radiosity.
struct TransportEntry {
    uint32_t patch = 0;  // j
    float factor = 0;  // F_ij
};

class Transport {
public:
    virtual ~Transport() = default;

    // The representation's name: "matrix".
    virtual const char* kind() const = 0;
    virtual uint32_t patchCount() const = 0;
    virtual TransportStats stats() const = 0;
    // sum_j F_ij per patch, in double: the share of light leaving i that reaches any patch.
    virtual std::span<const double> rowSums() const = 0;
    // What is wrong with the representation (a broken structure, a factor that is not finite),
    // or "" when nothing is: the stress suite's and tests' check.
    virtual std::string checkStructure() const = 0;

    // G = T B for B (n x m); each row summed in a fixed order, so the result does not depend on
    // `threads` (0: the calling arena's).
    virtual void gather(std::span<const double> radiosity, std::size_t wavelengthCount,
                        std::span<double> gathered, int threads = 0) const = 0;
    // G_i = sum over the sources j (sources[j] != 0) of F_ij B_j, for the patches with
    // receivers[i] != 0 (others left as they are); rows in column order. The final gather uses
    // it for the emitters' direct light.
    virtual void gatherFrom(std::span<const uint8_t> sources, std::span<const uint8_t> receivers,
                            std::span<const double> radiosity, std::size_t wavelengthCount,
                            std::span<double> gathered) const = 0;
    // The patches patch i gathers from directly, with their factors (`out` is replaced), in
    // ascending patch order: the near field's candidates.
    virtual void row(uint32_t patch, std::vector<TransportEntry>& out) const = 0;

    // Solves B = E + M T B for `system` (radiosity/solver.h: settings, stopping, cancellation,
    // warm start). settings.rowSums, when empty, are this transport's.
    virtual Expected<SolverResult> solve(const RadiositySystem& system,
                                         SolverSettings settings) const = 0;

    // Writes the transport as a Matrix Market file of F (radiosity/matrix_market.h) with
    // `comments`; an error for a representation that is not a matrix.
    virtual Expected<void> writeMatrixMarket(const std::string& path,
                                             const std::vector<std::string>& comments) const = 0;
    // Compares this transport's factors with `other`'s entry by entry (`daisy validate`); an
    // error when either is not a matrix or their sizes differ.
    virtual Expected<MatrixComparison> compare(const Transport& other,
                                               const MatrixCompareSettings& settings) const = 0;
};

}  // namespace daisy
