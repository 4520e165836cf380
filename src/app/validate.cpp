// `daisy validate SCENE --backend vulkan|cuda --against reference|cpu|vulkan|cuda` (DESIGN.md
// sections 8, 9):
// builds F twice with the same settings (same seed, so the pair backends draw the same samples),
// compares the matrices entry by entry over the union of their sparsity patterns and prints the
// largest differences, the worst entries and how many are over tolerance. Exit status: 0 every
// entry within tolerance, 1 some over, 2 bad input or a backend that cannot run (no device).
#include <cstdio>
#include <string>

#include "app/commands.h"
#include "app/session_options.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/strings.h"
#include "radiosity/transport.h"

namespace daisy::app {
namespace {

std::string shortNumber(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

std::string place(const EntryDifference& d) {
    return concat("(", d.row, ", ", d.column, ")");
}

int runValidate(const CommonOptions& options, const ValidateOptions& validate) {
    // Both matrices are built here, never read from the cache: comparing them is the point.
    // Shafts are culled wherever they can be, not where the cost model finds it pays: that
    // choice follows each backend's measured ray speed, so one backend would trace a pair the
    // other decides without rays, and the two answers differ where a segment grazes an edge.
    SessionSettings settings = sessionSettingsFrom(options, PatchSizeDefault::InputTriangles);
    settings.formFactors.costModel = false;
    auto session = Session::open(std::move(settings));
    if (!session) {
        logError(session.error().message);
        return 2;
    }
    auto tested = session->buildFormFactorsUncached(options.backend);
    if (!tested) {
        logError(tested.error().message);
        return 2;
    }
    const std::shared_ptr<const Transport> a = session->sharedTransport();
    auto against = session->buildFormFactorsUncached(validate.against);
    if (!against) {
        logError(against.error().message);
        return 2;
    }
    const Transport& b = session->transport();
    auto compared = a->compare(
        b, {validate.relativeTolerance, validate.absoluteTolerance, validate.worstShown});
    if (!compared) {
        logError(concat(options.scenePath, ": ", compared.error().message));
        return 2;
    }
    const MatrixComparison& c = *compared;
    const std::string& nameA = tested->backendName;
    const std::string& nameB = against->backendName;

    std::printf(
        "validate: %s against %s on %s: %s patches, method %s, quadrature %d, rays %d, "
        "seed %llu\n",
        nameA.c_str(), nameB.c_str(), options.scenePath.c_str(),
        formatCount(a->patchCount()).c_str(), options.method.c_str(), options.quadratureLevel,
        options.raysPerPair, static_cast<unsigned long long>(options.seed));
    std::printf("  %s: %s non-zeros in %s; %s: %s non-zeros in %s\n", nameA.c_str(),
                formatCount(a->stats().entries).c_str(),
                formatDuration(tested->stats.totalSeconds).c_str(), nameB.c_str(),
                formatCount(b.stats().entries).c_str(),
                formatDuration(against->stats.totalSeconds).c_str());
    std::printf("  union %s entries: %s only in %s, %s only in %s\n",
                formatCount(c.unionEntries).c_str(), formatCount(c.onlyInA).c_str(), nameA.c_str(),
                formatCount(c.onlyInB).c_str(), nameB.c_str());
    std::printf("  max absolute difference %s at %s; max relative difference %s at %s\n",
                shortNumber(c.maxAbsolute.absolute).c_str(), place(c.maxAbsolute).c_str(),
                shortNumber(c.maxRelative.relative).c_str(), place(c.maxRelative).c_str());
    if (!c.worst.empty()) {
        std::printf("  worst entries (i, j: %s, %s, absolute, relative difference):\n",
                    nameA.c_str(), nameB.c_str());
        for (const EntryDifference& d : c.worst) {
            std::printf("    %u, %u: %s, %s, %s, %s\n", d.row, d.column, shortNumber(d.a).c_str(),
                        shortNumber(d.b).c_str(), shortNumber(d.absolute).c_str(),
                        shortNumber(d.relative).c_str());
        }
    }
    std::printf("  over tolerance (|a - b| > %s max(|a|, |b|) + %s): %s of %s entries\n",
                shortNumber(validate.relativeTolerance).c_str(),
                shortNumber(validate.absoluteTolerance).c_str(),
                formatCount(c.overTolerance).c_str(), formatCount(c.unionEntries).c_str());
    std::printf("validate: %s\n", c.overTolerance == 0 ? "within tolerance" : "OVER TOLERANCE");
    std::fflush(stdout);
    return c.overTolerance == 0 ? 0 : 1;
}

}  // namespace

void addValidateCommand(CLI::App& app, CommandContext& context) {
    auto validate = std::make_shared<ValidateOptions>();
    CLI::App* command = context.add(app, "validate", "Compare a backend's matrix to another's");
    command->add_option("--against", validate->against, "Backend to compare with")
        ->check(CLI::IsMember({"reference", "cpu", "vulkan", "cuda"}))
        ->capture_default_str();
    command->add_option("--rtol", validate->relativeTolerance, "Relative tolerance per entry")
        ->check(finiteNumber(0, 1))
        ->capture_default_str();
    command->add_option("--atol", validate->absoluteTolerance, "Absolute tolerance per entry")
        ->check(finiteNumber(0, 1))
        ->capture_default_str();
    command->add_option("--worst", validate->worstShown, "Worst entries to list")
        ->check(CLI::Range(0, 1000000))
        ->capture_default_str();
    context.onRun(command, [&common = context.common, validate]() -> Expected<int> {
        if (common.backend != "vulkan" && common.backend != "cuda")
            return Error{"daisy validate: --backend must be vulkan or cuda"};
        if (validate->against == common.backend)
            return Error{"daisy validate: --against must name another backend than --backend"};
        return runValidate(common, *validate);
    });
}

}  // namespace daisy::app
