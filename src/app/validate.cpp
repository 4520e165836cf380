// `daisy validate SCENE --backend vulkan|cuda --against reference|cpu|vulkan|cuda` (DESIGN.md
// sections 8, 9):
// builds F twice with the same settings (same seed, so the pair backends draw the same samples),
// compares the matrices entry by entry over the union of their sparsity patterns and prints the
// largest differences, the worst entries and how many are over tolerance. Exit status: 0 every
// entry within tolerance, 1 some over, 2 bad input or a backend that cannot run (no device).
//
// `daisy validate SCENE --transport hierarchical [--against reference|cpu]`: the hierarchical
// transport has no entries to compare, so both transports are solved and their patch radiosity
// compared patch by patch (docs/hierarchical.md): exit 0 when the area-weighted RMS difference
// of the patches' radiosity (summed over the wavelengths) is within --rtol (default 1% here) of
// the area-weighted mean, 1 when over.
#include <algorithm>
#include <cmath>
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

// Per patch: its radiosity summed over the wavelength set (W m^-2).
std::vector<double> patchPower(const RadiositySystem& system, std::span<const double> b) {
    const std::size_t n = system.patchCount, m = system.wavelengthCount;
    std::vector<double> power(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t k = 0; k < m; ++k)
            power[i] += b[i * m + k] * system.binWidthsNm[k];
    }
    return power;
}

struct Solved {
    Session session;
    FormFactorReport report;
    std::vector<double> power;
};

Expected<Solved> solveWith(const CommonOptions& options, TransportKind transport,
                           const std::string& backend) {
    SessionSettings settings = sessionSettingsFrom(options, PatchSizeDefault::InputTriangles);
    settings.transport = transport;
    auto session = Session::open(std::move(settings));
    if (!session) return session.error();
    auto report = session->buildFormFactorsUncached(backend);
    if (!report) return report.error();
    auto solved = session->solve();
    if (!solved) return solved.error();
    std::vector<double> power = patchPower(session->system(), solved->radiosity);
    return Solved{std::move(*session), std::move(*report), std::move(power)};
}

int runValidatePatches(const CommonOptions& options, const ValidateOptions& validate,
                       double tolerance) {
    auto a = solveWith(options, TransportKind::Hierarchical, "cpu");
    if (!a) {
        logError(a.error().message);
        return 2;
    }
    auto b = solveWith(options, TransportKind::Matrix, validate.against);
    if (!b) {
        logError(b.error().message);
        return 2;
    }
    const std::vector<double>& areas = a->session.system().areas;
    const std::size_t n = areas.size();
    double sumSq = 0, sum = 0, area = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double d = a->power[i] - b->power[i];
        sumSq += areas[i] * d * d;
        sum += areas[i] * b->power[i];
        area += areas[i];
    }
    const double mean = area > 0 ? sum / area : 0;
    const double rms = mean > 0 ? std::sqrt(sumSq / area) / mean : 0;
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i)
        order[i] = i;
    const std::size_t shown = std::min<std::size_t>(n, std::size_t(validate.worstShown));
    std::partial_sort(
        order.begin(), order.begin() + shown, order.end(), [&](std::size_t x, std::size_t y) {
            return std::abs(a->power[x] - b->power[x]) > std::abs(a->power[y] - b->power[y]);
        });
    const TransportStats sa = a->session.transport().stats();
    const TransportStats sb = b->session.transport().stats();
    std::printf("validate: hierarchical (cpu) against matrix (%s) on %s: %s patches\n",
                b->report.backendName.c_str(), options.scenePath.c_str(), formatCount(n).c_str());
    std::printf(
        "  hierarchical: %s links and factors (%s) in %s; matrix: %s non-zeros (%s) in %s\n",
        formatCount(sa.entries).c_str(), formatBytes(double(sa.bytes)).c_str(),
        formatDuration(a->report.seconds).c_str(), formatCount(sb.entries).c_str(),
        formatBytes(double(sb.bytes)).c_str(), formatDuration(b->report.seconds).c_str());
    std::printf(
        "  patch radiosity (summed over the wavelengths): RMS difference %s of the mean "
        "(area-weighted)\n",
        shortNumber(rms).c_str());
    if (shown > 0) {
        std::printf("  worst patches (patch: hierarchical, matrix, relative difference):\n");
        for (std::size_t k = 0; k < shown; ++k) {
            const std::size_t i = order[k];
            const double larger = std::max(std::abs(a->power[i]), std::abs(b->power[i]));
            std::printf("    %zu: %s, %s, %s\n", i, shortNumber(a->power[i]).c_str(),
                        shortNumber(b->power[i]).c_str(),
                        shortNumber(larger > 0 ? (a->power[i] - b->power[i]) / larger : 0).c_str());
        }
    }
    std::printf("validate: %s (RMS %s, tolerance %s)\n",
                rms <= tolerance ? "within tolerance" : "OVER TOLERANCE", shortNumber(rms).c_str(),
                shortNumber(tolerance).c_str());
    std::fflush(stdout);
    return rms <= tolerance ? 0 : 1;
}

int runValidate(const CommonOptions& options, const ValidateOptions& validate) {
    // Both matrices are built here, never read from the cache: comparing them is the point.
    // Shafts are culled wherever they can be, not where the cost model finds it pays: that
    // choice follows each backend's measured ray speed, so one backend would trace a pair the
    // other decides without rays, and the two answers differ where a segment grazes an edge.
    SessionSettings settings = sessionSettingsFrom(options, PatchSizeDefault::InputTriangles);
    settings.transport = TransportKind::Matrix;  // entries to compare, whatever the scene's size
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
    context.onRun(command, [&common = context.common, validate, command]() -> Expected<int> {
        if (common.transport == "hierarchical") {
            if (common.backend != "auto" && common.backend != "cpu")
                return Error{
                    "daisy validate --transport hierarchical: the links are built on "
                    "the cpu backend; --against names the matrix's backend"};
            if (validate->against != "reference" && validate->against != "cpu")
                return Error{
                    "daisy validate --transport hierarchical: --against must be "
                    "reference or cpu"};
            const bool rtolGiven = command->get_option("--rtol")->count() > 0;
            return runValidatePatches(common, *validate,
                                      rtolGiven ? validate->relativeTolerance : 0.01);
        }
        if (common.backend != "vulkan" && common.backend != "cuda")
            return Error{"daisy validate: --backend must be vulkan or cuda"};
        if (validate->against == common.backend)
            return Error{"daisy validate: --against must name another backend than --backend"};
        return runValidate(common, *validate);
    });
}

}  // namespace daisy::app
