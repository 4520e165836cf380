// The stress suite's order and sizes (the cases are in stress_cases.cpp), and its table and CSV.
#include "bench/stress.h"

#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

#include "bench/stress_cases.h"
#include "core/strings.h"
#include "core/timer.h"
#include "pipeline/backend_registry.h"

namespace daisy {
namespace {

using namespace stress;

template <typename Case>
void run(std::vector<StressRow>& rows, const std::function<void(const StressRow&)>& onRow,
         Case&& body) {
    const auto start = Clock::now();
    StressRow row = body();
    row.seconds = secondsSince(start);
    if (!row.finite) row.pass = false;
    onRow(row);
    rows.push_back(std::move(row));
}

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

// printf into a string of whatever length the fields need.
template <typename... Args>
std::string formatted(const char* format, Args... args) {
    const int length = std::snprintf(nullptr, 0, format, args...);
    std::string text(std::size_t(length > 0 ? length : 0), '\0');
    std::snprintf(text.data(), text.size() + 1, format, args...);
    return text;
}

}  // namespace

std::vector<StressRow> runStressSuite(const StressSettings& settings,
                                      const std::function<void(const StressRow&)>& onRow) {
    std::vector<StressRow> rows;
    const bool quick = settings.quick;
    std::vector<std::shared_ptr<Backend>> backends;
    // Every backend that can run here (vulkan on whatever device exists: lavapipe in CI).
    for (const std::string& name : builtInBackendNames())
        if (auto backend = makeBackend(name)) backends.push_back(std::move(*backend));
    const Context solverOnly{settings, "-", nullptr};
    for (const auto& backend : backends) {
        const Context c{settings, backend->name(), backend};
        run(rows, onRow, [&] {
            return closedBoxRowSums(c, "closed cube", {1, 1, 1}, quick ? 4 : 8);
        });
        run(rows, onRow, [&] {
            return closedBoxRowSums(c, "sliver box 1 x 1e-4 x 1e-4", {1, 1e-4, 1e-4}, 1);
        });
        for (double rho : {0.99, 0.999})
            run(rows, onRow, [&] { return furnace(c, rho, quick ? 3 : 6); });
        const Built unit = buildAll(c, scaledRoom(1));
        for (double scale : {1e-3, 1e-2, 1e-1, 1e1, 1e2, 1e3, 1e4})
            run(rows, onRow, [&] { return scaleInvariance(c, scale, unit); });
        run(rows, onRow, [&] { return sliverStrips(c); });
        // gap 1e-3 fails (an open problem, docs/performance.md): full suite only, so ctest
        // guards what passes.
        if (!quick) run(rows, onRow, [&] { return nearlyCoincident(c, 1e-3, 4); });
        run(rows, onRow, [&] { return nearlyCoincident(c, 1e-6, quick ? 1 : 4); });
        for (double degrees : {1.0, 179.0})
            run(rows, onRow, [&] { return sharedEdge(c, degrees, quick ? 2 : 6); });
        run(rows, onRow, [&] { return coplanar(c, quick ? 6 : 20); });
        run(rows, onRow, [&] { return fluorescentChain(c, quick ? 3 : 6); });
        // The pair-kernel backends (reference, vulkan) evaluate all n^2 / 2 pairs (no cluster
        // culling): 5e9 at 1e5 patches took the reference over 20 minutes, so they get the
        // reduced row.
        const bool fullRow = !quick && c.backendName == "cpu";
        run(rows, onRow, [&] { return longRow(c, fullRow ? 224 : 71); });
    }
    for (double rho : {0.99, 0.999})
        run(rows, onRow, [&] { return furnaceExact(solverOnly, rho); });
    return rows;
}

std::string stressTableHeader() {
    return formatted("%-28s %-9s %8s %10s %10s %-6s %8s  %-4s  %s", "case", "backend", "patches",
                     "error", "tolerance", "finite", "time s", "", "oracle; status");
}

std::string stressTableRow(const StressRow& row) {
    return formatted("%-28s %-9s %8llu %10s %10s %-6s %8.3f  %-4s  %s; %s", row.name.c_str(),
                     row.backend.c_str(), static_cast<unsigned long long>(row.patches),
                     shortNumber(row.error).c_str(), shortNumber(row.tolerance).c_str(),
                     row.finite ? "yes" : "NO", row.seconds, row.pass ? "PASS" : "FAIL",
                     row.oracle.c_str(), row.status.c_str());
}

std::string stressCsv(const std::vector<StressRow>& rows, const std::string& command) {
    std::ostringstream out;
    out << "# " << command << "\n";
    out << "case,backend,patches,oracle,error,tolerance,finite,status,seconds,pass\n";
    for (const StressRow& row : rows) {
        out << csvField(row.name) << ',' << row.backend << ',' << row.patches << ','
            << csvField(row.oracle) << ',' << shortNumber(row.error) << ','
            << shortNumber(row.tolerance) << ',' << (row.finite ? "yes" : "no") << ','
            << csvField(row.status) << ',' << row.seconds << ',' << (row.pass ? "PASS" : "FAIL")
            << '\n';
    }
    return out.str();
}

Expected<void> writeStressCsv(const std::string& path, const std::vector<StressRow>& rows,
                              const std::string& command) {
    std::ofstream out(path);
    if (!out) return Error{concat(path, ": cannot open for writing")};
    out << stressCsv(rows, command);
    if (!out) return Error{concat(path, ": write failed")};
    return {};
}

}  // namespace daisy
