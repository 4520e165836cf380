// `daisy bench`: two modes. `--stress` runs the numerical stress suite (bench/stress.h) and
// prints one row per case (exit status 0 when every row passes, 1 otherwise); without it, run
// time against error, against the path-traced reference (bench/path_bench.h, the default) or
// a converged daisy (bench/sweep.h). All write CSV with -o. This file parses and prints; the
// runs, their errors and their files are the library's.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/session_options.h"
#include "bench/path_bench.h"
#include "bench/stress.h"
#include "bench/sweep.h"
#include "core/atomic_file.h"
#include "core/log.h"
#include "core/strings.h"
#include "core/timer.h"

namespace daisy::app {
namespace {

int runStress(const CommonOptions& options, const BenchOptions& bench) {
    // An unwritable -o fails now, not after the suite (core/atomic_file.h).
    auto reserved = reserveOutputs({bench.outputPath});
    if (!reserved) {
        logError(reserved.error().message);
        return 2;
    }
    StressSettings settings;
    settings.quick = bench.quick;
    settings.threads = options.threads;
    const auto start = Clock::now();
    if (!options.quiet) std::printf("%s\n", stressTableHeader().c_str());
    const std::vector<StressRow> rows = runStressSuite(settings, [&](const StressRow& row) {
        if (options.quiet && row.pass) return;
        std::printf("%s\n", stressTableRow(row).c_str());
        std::fflush(stdout);
    });
    const double seconds = secondsSince(start);
    std::size_t failures = 0;
    for (const StressRow& row : rows)
        failures += !row.pass;
    const std::string command =
        concat("daisy bench --stress", bench.quick ? " --quick" : "",
               options.threads ? concat(" --threads ", options.threads) : std::string());
    if (!bench.outputPath.empty()) {
        if (auto written = writeStressCsv(bench.outputPath, rows, command); !written) {
            logError(written.error().message);
            return 1;
        }
    }
    const std::string summary = concat("stress: ", rows.size() - failures, " of ", rows.size(),
                                       " cases pass in ", formatNumber(seconds, 3), " s");
    if (failures) {
        logError(summary);
        return 1;
    }
    logInfo(summary);
    return 0;
}

Expected<int> runSweep(const CommonOptions& options, const BenchOptions& bench) {
    if (options.scenePath.empty())
        return Error{"daisy bench: give a SCENE to sweep, or --stress for the stress suite"};
    SweepOptions sweepOptions;
    sweepOptions.session = sessionSettingsFrom(options, PatchSizeDefault::InputTriangles);
    sweepOptions.quick = bench.quick;
    const SweepFiles files = sweepFiles(options.scenePath, bench.outputPath, options.cacheDir);
    auto reserved = reserveOutputs({files.csv, files.chart, files.referenceImage});
    if (!reserved) return reserved.error();
    auto sweep = SettingsSweep::open(sweepOptions);
    if (!sweep) return sweep.error();
    auto reference = sweep->reference(files.referenceCache);
    if (!reference) return reference.error();
    logInfo(concat("bench: reference is ",
                   reference->analytic ? "the analytic furnace solution" : "the converged solution",
                   " (", formatCount(reference->patches), " patches, ", reference->samples,
                   " wavelengths, ", formatNumber(reference->seconds, 3), " s)"));

    std::vector<SweepRow> rows;
    logInfo(
        "  setting                          time s   F s      solve s  peak MB  mean dE00  "
        "rms B     rms Y");
    for (const SweepSetting& setting : sweep->settings()) {
        const SweepRow& row = rows.emplace_back(sweep->run(setting));
        if (!row.error.empty()) {
            logWarning(concat("bench: ", row.label, ": ", row.error));
            continue;
        }
        char line[256];
        std::snprintf(line, sizeof line,
                      "  %-32s %-8.3f %-8.3f %-8.3f %-8.0f %-10.3f %-9.2e %-9.2e",
                      concat(row.axis == "default" ? "" : row.axis + " ", row.label).c_str(),
                      row.totalSeconds, row.formFactorSeconds, row.solveSeconds,
                      row.peakBytes / 1e6, row.meanDeltaE, row.relativeRmsB, row.relativeRmsY);
        logInfo(line);
    }
    const int cheapest = markParetoFront(rows);
    if (auto written = sweep->writeFiles(files, rows); !written) {
        logError(written.error().message);
        return 1;
    }
    logInfo(concat("bench: wrote ", files.csv, ", ", files.chart, " and ", files.referenceImage));
    if (cheapest >= 0) {
        const SweepRow& row = rows[std::size_t(cheapest)];
        logInfo(concat("bench: cheapest setting under the just-noticeable difference: ", row.axis,
                       " ", row.label, " (", formatNumber(row.totalSeconds, 3), " s, mean dE00 ",
                       formatNumber(row.meanDeltaE, 3), ")"));
    } else {
        logInfo("bench: no setting is under the just-noticeable difference");
    }
    for (const SweepRow& row : rows)
        if (!row.error.empty()) return 1;
    return 0;
}

Expected<int> runPathBench(const CommonOptions& options, const BenchOptions& bench) {
    if (options.scenePath.empty()) return Error{"daisy bench --reference path: give a SCENE"};
    PathBenchOptions benchOptions;
    benchOptions.session = sessionSettingsFrom(options, PatchSizeDefault::Automatic);
    benchOptions.quick = bench.quick;
    benchOptions.referenceSpp = bench.referenceSpp;
    benchOptions.referenceNoisePercent = bench.referenceNoise;
    const PathBenchFiles files =
        pathBenchFiles(options.scenePath, bench.outputPath, options.cacheDir);
    auto reserved = reserveOutputs({files.csv, files.chart, files.referenceImage});
    if (!reserved) return reserved.error();
    auto pathBench = PathBench::open(benchOptions);
    if (!pathBench) return pathBench.error();
    const auto failed = [](const Error& error) {
        logError(error.message);
        return 1;
    };
    if (auto prepared = pathBench->prepare(); !prepared) return failed(prepared.error());
    auto reference = pathBench->reference(files.referenceCache);
    if (!reference) return reference.error();
    logInfo(concat("bench: reference ", reference->spp, " spp, ",
                   formatNumber(reference->seconds, 3), " s, relative RMS noise ",
                   formatNumber(100 * reference->noise, 3),
                   "% (emitter pixels and 2 around them left out)"));

    const auto report = [](const PathBenchRow& row) {
        if (row.kind == "refused") {
            logWarning(concat("  refused   ", row.label, " (", formatCount(row.patches),
                              " patches): no radiosity rows at this size or finer"));
            return;
        }
        char line[256];
        std::snprintf(line, sizeof line, "  %-9s %-26s %9.3f %8llu %9.2f%% %9.2f%% %8.3f %8.3f",
                      row.kind.c_str(), row.label.c_str(), row.seconds,
                      static_cast<unsigned long long>(row.patches),
                      100 * row.error.relativeRmsYDenoised, 100 * row.error.relativeRmsY,
                      row.error.meanDeltaE76, row.error.meanDeltaE2000);
        logInfo(line);
    };
    logInfo(
        "  kind      setting                       time s  patches  rms Y     rms Y raw  dE76     "
        "dE00");
    std::vector<PathBenchRow> rows;
    if (auto ran = pathBench->runPathRows(rows, report); !ran) return failed(ran.error());
    if (auto ran = pathBench->runRadiosityRows(files, rows, report); !ran)
        return failed(ran.error());
    if (auto written = pathBench->writeFiles(files, rows); !written) return failed(written.error());

    bool extrapolated = false;
    const double pathTo2 = pathTimeTo(rows, kPathBenchTargetError, extrapolated);
    logInfo(concat("bench: wrote ", files.csv, "; the path tracer reaches ",
                   formatNumber(100 * kPathBenchTargetError), "% in ", formatNumber(pathTo2, 3),
                   " s", extrapolated ? " (extrapolated from its last row as 1 / sqrt(time))" : "",
                   "; 1/20 of that is ", formatNumber(pathTo2 / 20, 3), " s"));
    return 0;
}

}  // namespace

void addBenchCommand(CLI::App& app, CommandContext& context) {
    auto bench = std::make_shared<BenchOptions>();
    CLI::App* command =
        context.add(app, "bench", "Benchmark run time against error", /*sceneRequired=*/false);
    command->add_flag("--stress", bench->stress, "Run the numerical stress suite");
    command->add_flag("--quick", bench->quick, "Reduced sizes (what ctest runs)");
    command->add_option("-o,--output", bench->outputPath, "CSV of the results");
    command
        ->add_option("--reference", bench->reference,
                     "What error is measured against: path (the path-traced reference) or daisy "
                     "(the settings sweep against a converged fine solution)")
        ->check(CLI::IsMember({"daisy", "path"}))
        ->capture_default_str();
    command
        ->add_option("--reference-spp", bench->referenceSpp,
                     "Samples per pixel of the path-traced reference (at most; traced in chunks "
                     "of 1,024, cached and resumed)")
        ->check(CLI::Range(1, 1 << 20))
        ->capture_default_str();
    command
        ->add_option("--reference-noise", bench->referenceNoise,
                     "Percent: stop the path-traced reference once its relative RMS noise is "
                     "under this (0: run to --reference-spp)")
        ->check(finiteNumber(0, 100))
        ->capture_default_str();
    context.onRun(command, [&common = context.common, bench]() -> Expected<int> {
        if (bench->stress) return runStress(common, *bench);
        return bench->reference == "path" ? runPathBench(common, *bench) : runSweep(common, *bench);
    });
}

}  // namespace daisy::app
