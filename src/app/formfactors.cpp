// `daisy formfactors SCENE -o F.mtx [--patches-out patches.csv]` (DESIGN.md section 9): a
// session on the scene, F from the cache or the chosen backend (the session prints the memory
// estimate and refuses over --max-memory), the Matrix Market file and the patch table, and a
// summary line.
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/session_options.h"
#include "core/atomic_file.h"
#include "core/interrupt.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/strings.h"
#include "radiosity/patch_csv.h"

namespace daisy::app {
namespace {

std::string percentOf(uint64_t part, uint64_t whole) {
    return whole == 0 ? "0%" : formatNumber(100.0 * double(part) / double(whole), 3) + "%";
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
                      " of them 0; ", formatCount(s.raysCast), " rays, ",
                      formatSi(s.pairSeconds > 0 ? double(s.raysCast) / s.pairSeconds : 0),
                      "rays/s over the pair loop"));
    if (s.costRayNs > 0) {
        const auto ns = [](double value) { return formatNumber(value, 3) + " ns"; };
        logVerbose(concat(
            "  cost model (fixed prices, one thread of the reference machine): a ray ",
            ns(s.costRayNs), ", a shaft with its query ", ns(s.costQueryNs), ", a shaft ",
            ns(s.costShaftNs), ", a polygon test ", ns(s.costTestNs), "; culled ",
            formatCount(s.culledClusterPairs), " cluster pairs, traced ",
            formatCount(s.costTracedClusterPairs), " without culling (rays cheaper), stopped ",
            formatCount(s.costStoppedRefinements), " refinements; culling priced at ",
            formatNumber(s.costCullNs * 1e-9, 3), " s, the rays it saved at ",
            formatNumber(s.costSavedNs * 1e-9, 3), " s; culling sampled only after ",
            formatCount(s.costGateClosedWaves), " waves where it had cost more than it saved"));
    } else if (s.culledClusterPairs > 0) {
        logVerbose(concat("  cost model off: culled all ", formatCount(s.culledClusterPairs),
                          " cluster pairs"));
    }
    if (s.rowsCapped > 0) {
        logVerbose(concat("  conservation: ", formatCount(s.rowsCapped),
                          " rows summed over 1 (the largest ", formatNumber(s.largestRowSum, 5),
                          ", sampled visibility) and were scaled to 1, reciprocity kept"));
    }
    logVerbose(concat("  time: candidates ", formatDuration(s.countSeconds), ", pairs ",
                      formatDuration(s.pairSeconds), ", compaction and conservation ",
                      formatDuration(s.compactSeconds), "; peak work memory ",
                      formatBytes(static_cast<double>(s.workBytes)), " for ", formatCount(s.slots),
                      " slots"));
}

int runFormFactors(const CommonOptions& given, const ExportOptions& exports) {
    if (given.transport == "hierarchical") {
        logError(concat("daisy formfactors writes the matrix F, which --transport ",
                        given.transport, " does not hold: use render, solve or info"));
        return 2;
    }
    CommonOptions options = given;
    options.transport = "matrix";  // what `auto` means here: the command writes F
    auto reserved = reserveOutputs({exports.matrixPath, exports.patchesPath});
    if (!reserved) {
        logError(reserved.error().message);
        return 2;
    }
    auto session = openSession(options, PatchSizeDefault::InputTriangles);
    if (!session) return 2;
    auto run = session->buildFormFactors(&interruptToken());
    if (!run) {
        logStageError(run.error());
        return 2;
    }
    const Transport& transport = session->transport();
    const FormFactorStats& stats = run->stats;

    const std::vector<std::string> comments = {
        "DaisyRiot view-factor matrix F: entry (i, j) = F_ij, the fraction of the energy leaving "
        "patch i that arrives at patch j (1-based patch indices; patches.csv lists them 0-based)",
        concat("scene ", options.scenePath, "; backend ",
               run->fromCache
                   ? concat(options.backend, " (F read from the cache ", run->cachePath, ")")
                   : run->backendName,
               "; method ", options.method, "; quadrature ", options.quadratureLevel, "; rays ",
               options.raysPerPair,
               options.method == "stochastic" ? concat("; stochastic rays ", options.stochasticRays)
                                              : std::string(),
               "; subdivide ", options.subdivideMaxEdge.value_or(0), "; seed ", options.seed)};
    if (auto written = transport.writeMatrixMarket(exports.matrixPath, comments); !written) {
        logError(written.error().message);
        return 1;
    }
    if (!exports.patchesPath.empty()) {
        std::vector<std::string> names;
        for (const Material& material : session->scene().materials)
            names.push_back(material.name);
        if (auto written = writePatchCsv(exports.patchesPath, session->patches(), names);
            !written) {
            logError(written.error().message);
            return 1;
        }
    }
    // The session has said where F came from; this line adds what was written and skipped.
    logInfo(concat("formfactors: wrote ", exports.matrixPath, " (",
                   formatCount(transport.stats().entries), " non-zeros, ",
                   formatBytes(static_cast<double>(transport.stats().bytes)), ", ", options.method,
                   "); pairs skipped without rays", run->fromCache ? " in the cached build" : "",
                   ": ", formatCount(stats.facingAway), " facing away, ",
                   formatCount(stats.clearClusterShafts + stats.clearPairShafts), " clear shafts, ",
                   formatCount(stats.coveredPairs), " covered; ", formatCount(stats.raysCast),
                   " rays cast"));
    printVerboseStats(stats);
    return 0;
}

}  // namespace

void addFormFactorsCommand(CLI::App& app, CommandContext& context) {
    auto exports = std::make_shared<ExportOptions>();
    CLI::App* command = context.add(app, "formfactors", "Compute the view-factor matrix");
    command->add_option("-o,--output", exports->matrixPath, "Matrix Market file")->required();
    command->add_option("--patches-out", exports->patchesPath, "Write patches as CSV");
    context.onRun(command,
                  [&common = context.common, exports] { return runFormFactors(common, *exports); });
}

}  // namespace daisy::app
