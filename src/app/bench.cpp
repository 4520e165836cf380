// `daisy bench` (issue 7): two modes. `--stress` runs the numerical stress suite (app/stress.h)
// and prints one row per case (exit status 0 when every row passes, 1 otherwise); without it,
// the time-vs-error sweep of app/bench_sweep.h. Both write CSV with -o.
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "app/bench_path.h"
#include "app/bench_sweep.h"
#include "app/commands.h"
#include "app/stress.h"
#include "core/log.h"
#include "core/strings.h"
#include "core/timer.h"

namespace daisy::app {
namespace {

std::string csvField(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text)
        quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

std::string shortNumber(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    return text;
}

void printStressHeader(bool quiet) {
    if (quiet) return;
    std::printf("%-28s %-9s %8s %10s %10s %-6s %8s  %-4s  %s\n", "case", "backend", "patches",
                "error", "tolerance", "finite", "time s", "", "oracle; status");
}

void printStressRow(const StressRow& row, bool quiet) {
    if (quiet && row.pass) return;
    std::printf("%-28s %-9s %8llu %10s %10s %-6s %8.3f  %-4s  %s; %s\n", row.name.c_str(),
                row.backend.c_str(), static_cast<unsigned long long>(row.patches),
                shortNumber(row.error).c_str(), shortNumber(row.tolerance).c_str(),
                row.finite ? "yes" : "NO", row.seconds, row.pass ? "PASS" : "FAIL",
                row.oracle.c_str(), row.status.c_str());
    std::fflush(stdout);
}

Expected<void> writeStressCsv(const std::string& path, const std::vector<StressRow>& rows,
                              const std::string& command) {
    std::ofstream out(path);
    if (!out) return Error{concat(path, ": cannot open for writing")};
    out << "# " << command << "\n";
    out << "case,backend,patches,oracle,error,tolerance,finite,status,seconds,pass\n";
    for (const StressRow& row : rows) {
        out << csvField(row.name) << ',' << row.backend << ',' << row.patches << ','
            << csvField(row.oracle) << ',' << shortNumber(row.error) << ','
            << shortNumber(row.tolerance) << ',' << (row.finite ? "yes" : "no") << ','
            << csvField(row.status) << ',' << row.seconds << ',' << (row.pass ? "PASS" : "FAIL")
            << '\n';
    }
    if (!out) return Error{concat(path, ": write failed")};
    return {};
}

int runStress(const CommonOptions& options, const BenchOptions& bench) {
    StressSettings settings;
    settings.quick = bench.quick;
    settings.threads = options.threads;
    const auto start = Clock::now();
    printStressHeader(options.quiet);
    const std::vector<StressRow> rows =
        runStressSuite(settings, [&](const StressRow& row) { printStressRow(row, options.quiet); });
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

}  // namespace

int runBench(const CommonOptions& options, const BenchOptions& bench) {
    if (bench.stress) return runStress(options, bench);
    return bench.reference == "path" ? runPathBench(options, bench) : runSweep(options, bench);
}

}  // namespace daisy::app
