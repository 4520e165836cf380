// `daisy formfactors SCENE -o F.mtx [--patches-out patches.csv]` (DESIGN.md section 9): load,
// build patches, print the memory estimate (refusing over --max-memory), build F on the chosen
// backend, write the Matrix Market file and the patch table, print a summary line.
#include <string>
#include <vector>

#include "app/commands.h"
#include "backend/backend.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/strings.h"
#include "geometry/patch_mesh.h"
#include "radiosity/matrix_estimate.h"
#include "radiosity/matrix_market.h"
#include "radiosity/patch_csv.h"

namespace daisy::app {
namespace {

std::string percentOf(uint64_t part, uint64_t whole) {
    return whole == 0 ? "0%" : formatNumber(100.0 * double(part) / double(whole), 3) + "%";
}

FormFactorSettings settingsFrom(const CommonOptions& options) {
    FormFactorSettings settings;
    parseFormFactorMethod(options.method, settings.method);  // CLI11 checked the name
    settings.quadratureLevel = options.quadratureLevel;
    settings.raysPerPair = options.raysPerPair;
    settings.stochasticRays = options.stochasticRays;
    settings.seed = options.seed;
    settings.threads = options.threads;
    settings.maxMemoryBytes = options.maxMemoryBytes;
    return settings;
}

void printVerboseStats(const FormFactorStats& s) {
    logVerbose(concat("  patches ", formatCount(s.patches), " in ", formatCount(s.clusters),
                      " coplanar clusters; ", formatCount(s.pairs), " unordered pairs"));
    logVerbose(concat("  skipped without rays: ", formatCount(s.facingAway), " facing away (",
                      percentOf(s.facingAway, s.pairs), "), ", formatCount(s.zeroFactor),
                      " with a zero unoccluded factor"));
    logVerbose(concat("  clear shafts (V = 1 without rays): ", formatCount(s.clearClusterShafts),
                      " by cluster pair, ", formatCount(s.clearPairShafts), " by pair (",
                      percentOf(s.clearClusterShafts + s.clearPairShafts, s.pairs), ")"));
    logVerbose(concat("  covered by a solid face (V = 0 without rays): ",
                      formatCount(s.coveredPairs), " (", percentOf(s.coveredPairs, s.pairs), ")"));
    logVerbose(concat("  traced: ", formatCount(s.tracedPairs), " pairs (",
                      percentOf(s.tracedPairs, s.pairs), "), ", formatCount(s.hiddenPairs),
                      " fully hidden; ", formatCount(s.raysCast), " rays, ",
                      formatSi(s.pairSeconds > 0 ? double(s.raysCast) / s.pairSeconds : 0),
                      "rays/s over the pair loop"));
    logVerbose(concat("  time: candidates ", formatDuration(s.countSeconds), ", pairs ",
                      formatDuration(s.pairSeconds), ", compaction ",
                      formatDuration(s.compactSeconds), "; peak work memory ",
                      formatBytes(static_cast<double>(s.workBytes)), " for ", formatCount(s.slots),
                      " slots"));
}

}  // namespace

int runFormFactors(const CommonOptions& options, const ExportOptions& exports) {
    auto scene = loadScene(options.scenePath, options.sceneLoadOptions());
    if (!scene) {
        logError(scene.error().message);
        return 2;
    }
    for (const std::string& warning : scene->warnings)
        logWarning(warning);

    const uint64_t patchLimit = options.maxMemoryBytes / kPatchMeshBytesPerPatch;
    auto patches = buildPatchMesh(scene->mesh, options.subdivideMaxEdge, patchLimit);
    if (!patches) {
        logError(concat(options.scenePath, ": ", patches.error().message, " (--max-memory ",
                        formatBytes(static_cast<double>(options.maxMemoryBytes)), ")"));
        return 2;
    }
    const MatrixEstimate estimate = estimateMatrixMemory(*patches);
    logInfo(concat("view factors: ", formatCount(patches->patchCount()), " patches, ~",
                   formatCount(estimate.nonzeros), " non-zeros, ~",
                   formatBytes(static_cast<double>(estimate.matrixBytes)), " as CSR (estimate)"));
    if (estimate.matrixBytes > options.maxMemoryBytes) {
        logError(concat(options.scenePath, ": the view-factor matrix needs about ",
                        formatBytes(static_cast<double>(estimate.matrixBytes)), " for ",
                        formatCount(patches->patchCount()), " patches, more than --max-memory ",
                        formatBytes(static_cast<double>(options.maxMemoryBytes)),
                        "; use a larger --subdivide or raise --max-memory"));
        return 2;
    }

    auto backend = makeBackend(options.backend);
    if (!backend) {
        logError(concat("--backend ", options.backend, ": ", backend.error().message));
        return 2;
    }
    const FormFactorSettings settings = settingsFrom(options);
    auto result = (*backend)->buildFormFactors(*patches, settings);
    if (!result) {
        logError(concat(options.scenePath, ": ", result.error().message));
        return 2;
    }
    const FormFactorStats& stats = result->stats;

    const std::vector<std::string> comments = {
        "DaisyRiot view-factor matrix F: entry (i, j) = F_ij, the fraction of the energy leaving "
        "patch i that arrives at patch j (1-based patch indices; patches.csv lists them 0-based)",
        concat("scene ", options.scenePath, "; backend ", (*backend)->name(), "; method ",
               options.method, "; quadrature ", options.quadratureLevel, "; rays ",
               options.raysPerPair,
               settings.method == FormFactorMethod::Stochastic
                   ? concat("; stochastic rays ", options.stochasticRays)
                   : std::string(),
               "; subdivide ", options.subdivideMaxEdge, "; seed ", options.seed)};
    if (auto written = writeMatrixMarket(exports.matrixPath, result->matrix, comments); !written) {
        logError(written.error().message);
        return 1;
    }
    if (!exports.patchesPath.empty()) {
        std::vector<std::string> names;
        for (const Material& material : scene->materials)
            names.push_back(material.name);
        if (auto written = writePatchCsv(exports.patchesPath, *patches, names); !written) {
            logError(written.error().message);
            return 1;
        }
    }
    logInfo(concat("view factors: ", formatCount(stats.nonzeros), " non-zeros (",
                   formatBytes(static_cast<double>(result->matrix.bytes())), ") in ",
                   formatDuration(stats.totalSeconds), " on ", (*backend)->name(), " (",
                   options.method, "); pairs skipped without rays: ", formatCount(stats.facingAway),
                   " facing away, ", formatCount(stats.clearClusterShafts + stats.clearPairShafts),
                   " clear shafts, ", formatCount(stats.coveredPairs), " covered; ",
                   formatCount(stats.raysCast), " rays cast"));
    printVerboseStats(stats);
    return 0;
}

}  // namespace daisy::app
