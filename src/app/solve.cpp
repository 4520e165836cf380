// `daisy solve SCENE [--patches-out patches.csv]` (DESIGN.md sections 6 and 9): load, choose
// the wavelength set (`auto` adds UV samples only for UV lights with fluorescent materials),
// build patches and F, assemble E and the per-material M, solve, print the summary line
// "solve: N iterations, residual R, T s" (and with --verbose the energy bookkeeping), and write
// the patch table with E_<nm>, B_<nm> per sample and X,Y,Z of B.
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/session_options.h"
#include "core/atomic_file.h"
#include "core/interrupt.h"
#include "core/log.h"
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

Expected<void> writeSolvedPatches(const std::string& path, const Session& session) {
    const RadiositySystem& system = session.system();
    const WavelengthSet& set = session.wavelengths();
    const std::vector<double>& radiosity = session.solution().radiosity;
    const std::size_t n = system.patchCount, m = system.wavelengthCount;
    PatchCsvColumns emission, solved, xyz;
    for (std::size_t k = 0; k < m; ++k) {
        emission.names.push_back("E_" + formatNumber(set.wavelengthNm(k)));
        solved.names.push_back("B_" + formatNumber(set.wavelengthNm(k)));
    }
    xyz.names = {"X", "Y", "Z"};
    std::vector<double> xyzValues(n * 3);
    for (std::size_t i = 0; i < n; ++i) {
        // X, Y, Z of B itself (exitance), not of the radiance B / pi.
        const Xyz c = set.toXyz(std::span<const double>(radiosity.data() + i * m, m));
        xyzValues[i * 3 + 0] = c[0];
        xyzValues[i * 3 + 1] = c[1];
        xyzValues[i * 3 + 2] = c[2];
    }
    emission.values = system.emission;
    solved.values = radiosity;
    xyz.values = xyzValues;
    std::vector<std::string> names;
    for (const Material& material : session.scene().materials)
        names.push_back(material.name);
    const PatchCsvColumns extra[] = {emission, solved, xyz};
    return writePatchCsv(path, session.patches(), names, extra);
}

int runSolve(const CommonOptions& options, const ExportOptions& exports) {
    auto reserved = reserveOutputs({exports.patchesPath});
    if (!reserved) {
        logError(reserved.error().message);
        return 2;
    }
    auto session = openSession(options, PatchSizeDefault::Automatic);  // render's patches
    if (!session) return 2;
    auto solved = session->solve(interruptibleSolve());
    if (!solved) {
        logStageError(solved.error());
        return 2;
    }
    if (verbosity() == Verbosity::Verbose) {
        printEnergy(session->energyBalance(), session->system());
    }
    if (!exports.patchesPath.empty()) {
        if (auto written = writeSolvedPatches(exports.patchesPath, *session); !written) {
            logError(written.error().message);
            return 1;
        }
    }
    return 0;
}

}  // namespace

void addSolveCommand(CLI::App& app, CommandContext& context) {
    auto exports = std::make_shared<ExportOptions>();
    CLI::App* command = context.add(app, "solve", "Solve spectral radiosity");
    command->add_option("--patches-out", exports->patchesPath, "Write patches as CSV");
    context.onRun(command,
                  [&common = context.common, exports] { return runSolve(common, *exports); });
}

}  // namespace daisy::app
