// The settings sweep's files, Pareto front, CSV and chart, and the furnace oracle
// (bench/sweep.h).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "bench/sweep.h"
#include "core/strings.h"

namespace daisy {
namespace {

std::string withExtension(const std::string& path, const std::string& suffix) {
    const std::filesystem::path p(path);
    return (p.parent_path() / p.stem()).string() + suffix;
}

std::string csvNumber(double value) {
    return std::isfinite(value) ? formatNumber(value, 6) : "";
}

}  // namespace

SweepFiles sweepFiles(const std::string& scenePath, const std::string& outputPath,
                      const std::string& cacheDir) {
    const std::string stem = std::filesystem::path(scenePath).stem().string();
    SweepFiles files;
    files.csv = outputPath.empty() ? concat("bench-", stem, ".csv") : outputPath;
    files.chart = withExtension(files.csv, ".png");
    files.referenceImage = withExtension(files.csv, "-reference.png");
    files.referenceCache = cacheDir.empty()
        ? withExtension(files.csv, ".reference.bin")
        : (std::filesystem::path(cacheDir) / (stem + ".bench-reference.bin")).string();
    return files;
}

ChartSpec sweepChart(const std::string& stem, const std::vector<SweepRow>& rows) {
    ChartSpec chart;
    chart.title = concat(stem, ": image error against run time (daisy bench)");
    chart.xLabel = "run time of the whole pipeline (s)";
    chart.yLabel = "mean CIEDE2000 against the reference";
    chart.referenceY = kJustNoticeableDeltaE;
    chart.referenceLabel = "just noticeable (1)";
    std::vector<std::string> axes;
    for (const SweepRow& row : rows) {
        auto found = std::find(axes.begin(), axes.end(), row.axis);
        const int series = int(found - axes.begin());
        if (found == axes.end()) axes.push_back(row.axis);
        // A perfect image (mean 0) sits at the bottom of a log axis: floor it at 1e-3.
        ChartPoint point{row.totalSeconds, std::max(row.meanDeltaE, 1e-3), series, row.label};
        if (!row.error.empty()) point.x = NAN;
        chart.points.push_back(point);
    }
    chart.seriesNames = axes;
    chart.front = paretoFront(chart.points);
    return chart;
}

int markParetoFront(std::vector<SweepRow>& rows) {
    int cheapest = -1;
    for (int k : sweepChart("", rows).front) {
        rows[std::size_t(k)].pareto = true;
        if (rows[std::size_t(k)].meanDeltaE < kJustNoticeableDeltaE && cheapest < 0) cheapest = k;
    }
    return cheapest;
}

std::string sweepCsv(const std::string& stem, const std::vector<SweepRow>& rows) {
    std::string csv =
        "scene,axis,setting,method,quadrature,rays,backend,patches,wavelengths,samples,tolerance,"
        "mesh_s,formfactors_s,solve_s,render_s,total_s,peak_bytes,nonzeros,iterations,residual,"
        "converged,rel_rms_B,rel_rms_Y,error_level,mean_dE00,p95_dE00,pareto,error\n";
    for (const SweepRow& row : rows) {
        std::string message = row.error;
        std::replace(message.begin(), message.end(), ',', ';');
        std::replace(message.begin(), message.end(), '\n', ' ');
        csv += concat(stem, ",", row.axis, ",", row.label, ",", row.method, ",",
                      row.quadratureLevel, ",", row.raysPerPair, ",", row.backend, ",", row.patches,
                      ",", row.wavelengths, ",", row.samples, ",", formatNumber(row.tolerance), ",",
                      csvNumber(row.meshSeconds), ",", csvNumber(row.formFactorSeconds), ",",
                      csvNumber(row.solveSeconds), ",", csvNumber(row.renderSeconds), ",",
                      csvNumber(row.totalSeconds), ",", row.peakBytes, ",", row.nonzeros, ",",
                      row.iterations, ",", csvNumber(row.residual), ",", row.converged ? 1 : 0, ",",
                      csvNumber(row.relativeRmsB), ",", csvNumber(row.relativeRmsY), ",",
                      row.errorLevel, ",", csvNumber(row.meanDeltaE), ",", csvNumber(row.p95DeltaE),
                      ",", row.pareto ? 1 : 0, ",", message, "\n");
    }
    return csv;
}

std::optional<std::vector<double>> furnaceSolution(const PatchMesh& patches,
                                                   const RadiositySystem& system) {
    if (system.operators.size() != 1 || !system.operators[0].isDiagonal) return std::nullopt;
    const std::size_t n = system.patchCount, m = system.wavelengthCount;
    for (std::size_t i = 1; i < n; ++i)
        if (!std::equal(system.emissionRow(0), system.emissionRow(0) + m, system.emissionRow(i)))
            return std::nullopt;
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (const auto& corners : patches.patches)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = corners[e], b = corners[(e + 1) % 3];
            ++edges[{std::min(a, b), std::max(a, b)}];
        }
    for (const auto& [edge, count] : edges)
        if (count != 2) return std::nullopt;
    const std::vector<double>& rho = system.operators[0].diagonal;
    std::vector<double> radiosity(n * m);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < m; ++k) {
            if (rho[k] >= 1) return std::nullopt;
            radiosity[i * m + k] = system.emissionRow(i)[k] / (1 - rho[k]);
        }
    return radiosity;
}

}  // namespace daisy
