#pragma once
// The form-factor driver (DESIGN.md section 3): builds the sparse view-factor matrix F of a
// PatchMesh with one of four methods, visibility from a backend's RayCaster, each unordered pair
// computed once and its mirror entry filled by reciprocity A_i F_ij = A_j F_ji.
//
// Pair loop: rows are cut into clusters (runs of coplanar patches, radiosity/patch_clusters.h),
// grouped into row blocks of >= 32 rows, one TBB task each. A task computes F_ij for its rows i
// and every column j > i, cluster pair by cluster pair, and writes both F_ij and its mirror
// F_ji = F_ij A_i / A_j straight into the CSR arrays. A first pass marks the candidate pairs
// (not facing away) in a bitmap and counts them per row and per (row block, column), which
// sizes every row exactly and tells each block where its mirrored entries go; so memory is the
// CSR itself plus n^2/16 bytes of bitmap and n^2/8 of block tables, never triplets. Stored
// zeros (pairs found fully hidden) are dropped at the end. Every value is a pure function of
// (i, j, settings) and of the culling's choices, which depend on the geometry, the settings and
// the backend alone (never on timings), so F is bit-identical for any thread count and load.
//
// Backends: every one hands the driver a PairEvaluator (radiosity/pair_evaluator.h) that returns
// F_ij and F_ji of a batch of pairs; the kernels' inputs are radiosity/kernel_inputs.h. The
// driver's files, by concern: form_factors.cpp (these entry points), form_factors_candidates.cpp,
// form_factors_culling.cpp, form_factors_cost_model.cpp and form_factors_pair_loop.cpp
// (docs/formfactors.md, "Where the code is").
//
// Visibility V_ij: K shadow segments between stratified points (shared/sampling.h), any-hit.
// Skipped when it cannot change the answer: facing-away pairs are 0 without rays; pairs whose
// shaft (conv(i u j)) nothing else enters get V = 1, and pairs whose shaft one solid face crosses
// entirely get V = 0, without rays (radiosity/shaft.h, patch_clusters.h): tested for the whole
// cluster pair, then for ever smaller node pairs against the short list of blockers left.
#include <cstdint>
#include <string>
#include <vector>

#include "core/cancel.h"
#include "core/expected.h"
#include "core/progress.h"
#include "geometry/patch_mesh.h"
#include "radiosity/pair_evaluator.h"
#include "radiosity/sparse_matrix.h"
#include "raycast/ray_caster.h"

namespace daisy {

enum class FormFactorMethod { Riemann, Nusselt, Stochastic, Hybrid };

// "riemann" -> Riemann, ...; false for unknown names.
bool parseFormFactorMethod(const std::string& name, FormFactorMethod& method);
const char* formFactorMethodName(FormFactorMethod method);
// Every method name, the default (hybrid) first.
std::vector<std::string> formFactorMethodNames();

struct FormFactorSettings {
    FormFactorMethod method = FormFactorMethod::Hybrid;
    int quadratureLevel = 1;  // L: 4^L quadrature cells per patch (riemann, hybrid)
    // K shadow segments per pair; 0 = no visibility (V = 1). 4: chosen by `daisy bench`
    // (docs/performance.md, "Choosing the defaults"); the command line's default is this one.
    int raysPerPair = 4;
    int stochasticRays = 1024;  // N rays per patch (stochastic)
    uint64_t seed = 1;  // of every sample sequence
    int threads = 0;  // worker threads; 0 = all hardware threads
    uint64_t maxMemoryBytes = 0;  // refuse a build needing more; 0 = no limit
    bool shaftCulling = true;  // off only to measure what it saves
    // With shaft culling: per cluster pair and per refinement step, cull only where the cost
    // model prices the shafts below the rays they could save (fixed prices times counted work,
    // so F does not depend on the machine's load); off = always cull (benchmarks only).
    bool costModel = true;
    bool progress = true;  // progress line on a terminal (core/progress.h decides if shown)
    ProgressObserver onProgress;  // told of the pair loop's progress (core/progress.h); optional
    // Polled between row blocks / batches; when cancelled the build stops and returns the Error
    // kInterruptedMessage. Null = never cancelled. interruptToken() (core/interrupt.h) for SIGINT.
    const CancelToken* cancel = nullptr;
};

// The message of a build stopped by FormFactorSettings::cancel.
inline constexpr const char* kInterruptedMessage = "interrupted";

struct FormFactorStats {
    uint64_t patches = 0;
    uint64_t pairs = 0;  // unordered pairs i < j
    uint64_t facingAway = 0;  // pairs skipped: no part of one is in front of the other
    uint64_t zeroFactor = 0;  // visible candidate pairs whose unoccluded factor is 0
    uint64_t clearClusterShafts = 0;  // pairs with V = 1 from a clear cluster-pair shaft
    uint64_t clearPairShafts = 0;  // pairs with V = 1 from a clear refined (smaller) shaft
    uint64_t coveredPairs = 0;  // pairs with V = 0 without rays: a solid face cuts the shaft
    uint64_t tracedPairs = 0;  // pairs whose visibility was ray cast
    uint64_t hiddenPairs = 0;  // traced pairs whose F came out 0 (hidden, or a zero factor)
    uint64_t raysCast = 0;  // shadow segments (or stochastic rays)
    uint64_t clusters = 0;
    uint64_t shaftsBuilt = 0;  // shafts constructed for culling
    // The cost model (form_factors_cost_model.cpp): cluster pairs culled, cluster pairs traced
    // because their rays cost less than a shaft query, node pairs traced because smaller shafts
    // would cost more than their rays; its prices, in nanoseconds of one thread of the reference
    // machine (fixed, not timed: 0 when the model was off): a segment (the backend's), a
    // cluster pair's shaft with its query (estimated on this scene from counted work), a shaft
    // and a shaft-polygon test; what the culling done was priced at and what it saved (the
    // rays of the pairs it decided), and the waves after which culling had cost more than it
    // saved (then only sampled).
    uint64_t culledClusterPairs = 0;
    uint64_t costTracedClusterPairs = 0;
    uint64_t costStoppedRefinements = 0;
    double costRayNs = 0;
    double costQueryNs = 0;
    double costShaftNs = 0;
    double costTestNs = 0;
    double costCullNs = 0;
    double costSavedNs = 0;
    uint64_t costGateClosedWaves = 0;
    // Conservation (capRowSums, radiosity/sparse_matrix.h; only with visibility rays): rows
    // whose sum came out over 1 and were scaled down, and the largest row sum before that.
    uint64_t rowsCapped = 0;
    double largestRowSum = 0;
    uint64_t slots = 0;  // CSR entries allocated before zeros were dropped
    uint64_t nonzeros = 0;
    uint64_t workBytes = 0;  // peak bytes of the build: CSR slots + bitmap + scratch
    double countSeconds = 0;  // candidate pass
    double pairSeconds = 0;  // pair loop (factors and visibility)
    double compactSeconds = 0;  // removal of the stored zeros and capRowSums
    double totalSeconds = 0;
};

struct FormFactorResult {
    SparseMatrix matrix;
    FormFactorStats stats;
};

// Bytes the build will hold at its peak for `candidatePairs` unordered candidate pairs among n
// patches: the CSR with 2 x candidatePairs slots, the candidate bitmap, the row blocks' column
// tables, per-thread scratch and a wave's pending pairs, with row blocks of at most
// `blockRows` rows (the usual 2 x 32 unless clusters of scattered runs are larger:
// radiosity/patch_clusters.h).
uint64_t formFactorWorkBytes(uint64_t patchCount, uint64_t candidatePairs, uint64_t blockRows = 64);

// Builds F. Fails with a message (exit status 2 in the app) when the settings are out of range
// or the build would need more than settings.maxMemoryBytes. The cpu backend's form: pairs
// evaluated by radiosity/ray_pair_evaluator.h over `rays`; stochastic runs here too.
Expected<FormFactorResult> computeFormFactors(const PatchMesh& mesh,
                                              const FormFactorSettings& settings,
                                              const RayCaster& rays);
// The same driver over any backend's pair evaluation (riemann, nusselt and hybrid; stochastic
// is refused with a message naming the backend). The driver stores each pair's F_ij from the
// evaluator and derives F_ji = F_ij A_i / A_j from the mesh's areas.
Expected<FormFactorResult> computeFormFactors(const PatchMesh& mesh,
                                              const FormFactorSettings& settings,
                                              PairEvaluator& evaluator);

// The error computeFormFactors(..., evaluator) returns for a method that is not a pair method
// (stochastic: its rays are per patch), naming `backend`; so a backend can refuse before it
// uploads anything. Success for riemann, nusselt and hybrid.
Expected<void> checkPairMethod(const FormFactorSettings& settings, const std::string& backend);

}  // namespace daisy
