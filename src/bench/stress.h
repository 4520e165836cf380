#pragma once
// The numerical stress suite behind `daisy bench --stress`: small scenes built in code that push
// the real pipeline (buildPatchMesh, every available backend's computeFormFactors, the solvers,
// the energy bookkeeping) to the edges of its numerics, each checked against a closed form or a
// conservation law. docs/performance.md lists the cases, their oracles and the results.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/expected.h"

namespace daisy {

// One case's outcome: a row of the table.
struct StressRow {
    std::string name;  // "furnace rho=0.999"
    std::string backend;  // "cpu", "reference", or "-" for solver-only cases
    uint64_t patches = 0;
    std::string oracle;  // what the error is measured against
    double error = 0;  // in the oracle's measure (see `oracle`)
    double tolerance = 0;
    bool finite = true;  // no NaN or infinity in F, B or the derived values
    std::string status;  // "converged (N it)", "n/a", or the diagnosis
    double seconds = 0;  // wall time of the case
    bool pass = false;
};

struct StressSettings {
    bool quick = false;  // reduced sizes (ctest)
    int threads = 0;  // 0 = all hardware threads
};

// Runs every case on every backend makeBackend builds here (cpu, reference, vulkan with a device),
// calling `onRow` as each row is finished (for a live table). Deterministic for fixed settings.
std::vector<StressRow> runStressSuite(const StressSettings& settings,
                                      const std::function<void(const StressRow&)>& onRow);

// The table as `daisy bench --stress` prints it: the header line and one line per row (fixed
// columns, no newline; numbers to 3 significant digits, time in seconds).
std::string stressTableHeader();
std::string stressTableRow(const StressRow& row);

// The rows as CSV: "# command", the header, one line per row; text fields quoted as RFC 4180
// says (in double quotes, quotes doubled) when they hold a comma, a quote or a newline.
std::string stressCsv(const std::vector<StressRow>& rows, const std::string& command);

// stressCsv written to `path`; the error names the file.
Expected<void> writeStressCsv(const std::string& path, const std::vector<StressRow>& rows,
                              const std::string& command);

}  // namespace daisy
