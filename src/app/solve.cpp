// `daisy solve SCENE [--patches-out patches.csv]` (DESIGN.md sections 6 and 9): load, choose
// the wavelength set (`auto` adds UV samples only for UV lights with fluorescent materials),
// build patches and F, assemble E and the per-material M, solve, print the summary line
// "solve: N iterations, residual R, T s" (and with --verbose the energy bookkeeping), and write
// the patch table with E_<nm>, B_<nm> per sample and X,Y,Z of B.
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/pipeline.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/strings.h"
#include "radiosity/energy.h"
#include "radiosity/patch_csv.h"
#include "radiosity/radiosity_system.h"
#include "radiosity/solver.h"
#include "spectral/wavelength_set.h"

namespace daisy::app {
namespace {

std::string watts(double value) {
    return formatNumber(value, 5);
}

void printEnergy(const EnergyBalance& e, const RadiositySystem& system) {
    const auto share = [&](double part) {
        return e.emitted > 0 ? concat(" (", formatNumber(100 * part / e.emitted, 4), "%)") : "";
    };
    logVerbose("energy (W per unit emission scale, sum_i A_i sum_k w_k x_ik):");
    logVerbose(concat("  emitted    ", watts(e.emitted)));
    logVerbose(concat("  absorbed   ", watts(e.absorbed), share(e.absorbed)));
    logVerbose(concat("  escaped    ", watts(e.escaped), share(e.escaped),
                      "  (through openings: 1 - row sum)"));
    logVerbose(concat("  converted  ", watts(e.converted), share(e.converted),
                      "  (re-emitted by fluorescence at longer wavelengths)"));
    logVerbose(concat("  incident   ", watts(e.incident), ", reflected ", watts(e.reflected)));
    logVerbose(concat("  balance    (emitted - absorbed - escaped) / emitted = ",
                      formatNumber(e.imbalance(), 3)));
    logVerbose("  per sample: nm, emitted, absorbed, escaped, fluorescence in");
    for (std::size_t k = 0; k < system.wavelengthCount; ++k) {
        logVerbose(concat("    ", formatNumber(system.wavelengthsNm[k]), "  ",
                          watts(e.emittedPerSample[k]), "  ", watts(e.absorbedPerSample[k]), "  ",
                          watts(e.escapedPerSample[k]), "  ", watts(e.convertedInPerSample[k])));
    }
}

Expected<void> writeSolvedPatches(const std::string& path, const Scene& scene,
                                  const PatchMesh& patches, const RadiositySystem& system,
                                  const WavelengthSet& set, const std::vector<double>& radiosity) {
    const std::size_t n = system.patchCount, m = system.wavelengthCount;
    PatchCsvColumns emission, solved, xyz;
    for (std::size_t k = 0; k < m; ++k) {
        emission.names.push_back("E_" + formatNumber(set.wavelengthNm(k)));
        solved.names.push_back("B_" + formatNumber(set.wavelengthNm(k)));
    }
    xyz.names = {"X", "Y", "Z"};
    std::vector<double> xyzValues(n * 3);
    for (std::size_t i = 0; i < n; ++i) {
        const Xyz c = set.toXyz(std::span<const double>(radiosity.data() + i * m, m));
        xyzValues[i * 3 + 0] = c[0];
        xyzValues[i * 3 + 1] = c[1];
        xyzValues[i * 3 + 2] = c[2];
    }
    emission.values = system.emission;
    solved.values = radiosity;
    xyz.values = xyzValues;
    std::vector<std::string> names;
    for (const Material& material : scene.materials)
        names.push_back(material.name);
    const PatchCsvColumns extra[] = {emission, solved, xyz};
    return writePatchCsv(path, patches, names, extra);
}

}  // namespace

int runSolve(const CommonOptions& options, const ExportOptions& exports) {
    auto scene = loadSceneLogged(options);
    if (!scene) {
        logError(scene.error().message);
        return 2;
    }
    auto facts = sceneSpectralFacts(*scene);
    if (!facts) {
        logError(facts.error().message);
        return 2;
    }
    auto set =
        makeWavelengthSet(options.wavelengthSpec, facts->hasUvLights, facts->hasFluorescence);
    if (!set) {
        logError(concat("--wavelengths ", options.wavelengths, ": ", set.error().message));
        return 2;
    }
    auto patches = buildPatchesWithin(options, *scene, options.subdivideMaxEdge.value_or(0));
    if (!patches) {
        logError(patches.error().message);
        return 2;
    }
    auto system = buildRadiositySystem(*scene, *patches, *set);
    if (!system) {
        logError(system.error().message);
        return 2;
    }
    auto formFactors = buildFormFactorsFor(options, *patches);
    if (!formFactors) {
        logError(formFactors.error().message);
        return 2;
    }
    const SparseMatrix& f = formFactors->result.matrix;
    logInfo(concat("view factors: ", formatCount(f.nonzeroCount()), " non-zeros in ",
                   formatDuration(formFactors->result.stats.totalSeconds), " on ",
                   formFactors->backendName));

    std::size_t fluorescent = 0;
    for (const MaterialOperator& op : system->operators)
        fluorescent += !op.isDiagonal;
    logVerbose(concat("wavelengths: ", set->name(), ", ", set->size(), " samples ",
                      formatNumber(set->wavelengthNm(0)), "..",
                      formatNumber(set->wavelengthNm(set->size() - 1)), " nm",
                      facts->hasUvLights && facts->hasFluorescence
                          ? " (scene has UV lights and fluorescent materials)"
                          : ""));
    logVerbose(concat("materials: ", scene->materials.size(), " as ", system->operators.size(),
                      " distinct re-radiation matrices, ", fluorescent, " fluorescent",
                      fluorescent ? "" : " (wavelengths solved independently, M diagonal)"));

    SolverSettings settings;
    parseSolverKind(options.solver, settings.kind);  // CLI11 checked the name
    settings.tolerance = options.tolerance;
    settings.maxIterations = options.maxIterations;
    settings.threads = options.threads;
    auto solved = solveRadiosity(f, *system, settings);
    if (!solved) {
        logError(concat(options.scenePath, ": ", solved.error().message));
        return 2;
    }
    if (!solved->converged) logWarning(concat(options.scenePath, ": ", solved->warning));
    logInfo(concat("solve: ", solved->iterations, " iterations, residual ",
                   formatNumber(solved->residual, 3), ", ", formatNumber(solved->seconds, 3),
                   " s (", options.solver, ", ", formatCount(system->patchCount), " patches x ",
                   system->wavelengthCount, " wavelengths", fluorescent ? ", fluorescence" : "",
                   ")"));
    if (verbosity() == Verbosity::Verbose) {
        const std::vector<double> sums = rowSums(f);
        printEnergy(computeEnergyBalance(*system, sums, solved->radiosity, solved->gathered),
                    *system);
    }

    if (!exports.patchesPath.empty()) {
        if (auto written = writeSolvedPatches(exports.patchesPath, *scene, *patches, *system, *set,
                                              solved->radiosity);
            !written) {
            logError(written.error().message);
            return 1;
        }
    }
    return 0;
}

}  // namespace daisy::app
