// `daisy validate SCENE --backend vulkan|cuda --against reference|cpu` (DESIGN.md sections 8, 9):
// builds F twice with the same settings (same seed, so the pair backends draw the same samples),
// compares the matrices entry by entry over the union of their sparsity patterns and prints the
// largest differences, the worst entries and how many are over tolerance. Exit status: 0 every
// entry within tolerance, 1 some over, 2 bad input or a backend that cannot run (no device).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/session_options.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/strings.h"

namespace daisy::app {
namespace {

struct EntryDifference {
    uint32_t row = 0;
    uint32_t column = 0;
    float tested = 0;  // the --backend value (0 when not stored)
    float against = 0;  // the --against value
    double absolute = 0;  // |tested - against|
    double relative = 0;  // absolute / max(|tested|, |against|)
    double excess = 0;  // absolute / tolerance of the entry: > 1 is over tolerance
};

struct Comparison {
    uint64_t unionEntries = 0;  // entries stored in either matrix
    uint64_t onlyTested = 0;  // stored in the tested matrix only
    uint64_t onlyAgainst = 0;
    uint64_t overTolerance = 0;
    EntryDifference maxAbsolute;
    EntryDifference maxRelative;
    std::vector<EntryDifference> worst;  // by excess, largest first, at most worstShown
};

// Walks both CSR matrices row by row in column order (the union of the patterns). An entry agrees
// when |a - b| <= rtol max(|a|, |b|) + atol; entries are ranked by |a - b| over that bound (by
// |a - b| when both tolerances are 0).
Comparison compareMatrices(const SparseMatrix& tested, const SparseMatrix& against,
                           const ValidateOptions& validate) {
    Comparison c;
    const auto byExcess = [](const EntryDifference& a, const EntryDifference& b) {
        return a.excess > b.excess;
    };
    const auto consider = [&](uint32_t row, uint32_t column, float a, float b) {
        EntryDifference d{row, column, a, b};
        const double scale = std::max(std::abs(double(a)), std::abs(double(b)));
        d.absolute = std::abs(double(a) - double(b));
        d.relative = scale > 0 ? d.absolute / scale : 0;
        const double bound = validate.relativeTolerance * scale + validate.absoluteTolerance;
        d.excess = bound > 0 ? d.absolute / bound : d.absolute;
        if (d.absolute > bound) ++c.overTolerance;
        if (d.absolute > c.maxAbsolute.absolute) c.maxAbsolute = d;
        if (d.relative > c.maxRelative.relative) c.maxRelative = d;
        if (validate.worstShown <= 0 || d.absolute == 0) return;
        if (c.worst.size() < std::size_t(validate.worstShown)) {
            c.worst.push_back(d);
            std::push_heap(c.worst.begin(), c.worst.end(), byExcess);
        } else if (d.excess > c.worst.front().excess) {
            std::pop_heap(c.worst.begin(), c.worst.end(), byExcess);
            c.worst.back() = d;
            std::push_heap(c.worst.begin(), c.worst.end(), byExcess);
        }
    };
    for (uint32_t row = 0; row < tested.size; ++row) {
        const auto ca = tested.rowColumns(row), cb = against.rowColumns(row);
        const auto va = tested.rowValues(row), vb = against.rowValues(row);
        std::size_t p = 0, q = 0;
        while (p < ca.size() || q < cb.size()) {
            ++c.unionEntries;
            if (q == cb.size() || (p < ca.size() && ca[p] < cb[q])) {
                ++c.onlyTested;
                consider(row, ca[p], va[p], 0.0f);
                ++p;
            } else if (p == ca.size() || cb[q] < ca[p]) {
                ++c.onlyAgainst;
                consider(row, cb[q], 0.0f, vb[q]);
                ++q;
            } else {
                consider(row, ca[p], va[p], vb[q]);
                ++p, ++q;
            }
        }
    }
    std::sort_heap(c.worst.begin(), c.worst.end(), byExcess);
    return c;
}

std::string shortNumber(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

std::string place(const EntryDifference& d) {
    return concat("(", d.row, ", ", d.column, ")");
}

}  // namespace

int runValidate(const CommonOptions& options, const ValidateOptions& validate) {
    // Both matrices are built here, never read from the cache: comparing them is the point.
    auto session = openSession(options, PatchSizeDefault::InputTriangles);
    if (!session) return 2;
    auto tested = session->buildFormFactorsUncached(options.backend);
    if (!tested) {
        logError(tested.error().message);
        return 2;
    }
    const SparseMatrix a = session->formFactors();
    auto against = session->buildFormFactorsUncached(validate.against);
    if (!against) {
        logError(against.error().message);
        return 2;
    }
    const SparseMatrix& b = session->formFactors();
    DAISY_CHECK_OP(a.size, ==, b.size);
    const Comparison c = compareMatrices(a, b, validate);
    const std::string& nameA = tested->backendName;
    const std::string& nameB = against->backendName;

    std::printf(
        "validate: %s against %s on %s: %s patches, method %s, quadrature %d, rays %d, "
        "seed %llu\n",
        nameA.c_str(), nameB.c_str(), options.scenePath.c_str(), formatCount(a.size).c_str(),
        options.method.c_str(), options.quadratureLevel, options.raysPerPair,
        static_cast<unsigned long long>(options.seed));
    std::printf("  %s: %s non-zeros in %s; %s: %s non-zeros in %s\n", nameA.c_str(),
                formatCount(a.nonzeroCount()).c_str(),
                formatDuration(tested->stats.totalSeconds).c_str(), nameB.c_str(),
                formatCount(b.nonzeroCount()).c_str(),
                formatDuration(against->stats.totalSeconds).c_str());
    std::printf("  union %s entries: %s only in %s, %s only in %s\n",
                formatCount(c.unionEntries).c_str(), formatCount(c.onlyTested).c_str(),
                nameA.c_str(), formatCount(c.onlyAgainst).c_str(), nameB.c_str());
    std::printf("  max absolute difference %s at %s; max relative difference %s at %s\n",
                shortNumber(c.maxAbsolute.absolute).c_str(), place(c.maxAbsolute).c_str(),
                shortNumber(c.maxRelative.relative).c_str(), place(c.maxRelative).c_str());
    if (!c.worst.empty()) {
        std::printf("  worst entries (i, j: %s, %s, absolute, relative difference):\n",
                    nameA.c_str(), nameB.c_str());
        for (const EntryDifference& d : c.worst) {
            std::printf("    %u, %u: %s, %s, %s, %s\n", d.row, d.column,
                        shortNumber(d.tested).c_str(), shortNumber(d.against).c_str(),
                        shortNumber(d.absolute).c_str(), shortNumber(d.relative).c_str());
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

}  // namespace daisy::app
