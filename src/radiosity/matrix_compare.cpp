#include "radiosity/matrix_compare.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace daisy {

MatrixComparison compareMatrices(const SparseMatrix& a, const SparseMatrix& b,
                                 const MatrixCompareSettings& settings) {
    DAISY_CHECK_OP(a.size, ==, b.size);
    MatrixComparison c;
    const auto byExcess = [](const EntryDifference& x, const EntryDifference& y) {
        return x.excess > y.excess;
    };
    const auto consider = [&](uint32_t row, uint32_t column, float x, float y) {
        EntryDifference d{row, column, x, y};
        const double scale = std::max(std::abs(double(x)), std::abs(double(y)));
        d.absolute = std::abs(double(x) - double(y));
        d.relative = scale > 0 ? d.absolute / scale : 0;
        const double bound = settings.relativeTolerance * scale + settings.absoluteTolerance;
        d.excess = bound > 0 ? d.absolute / bound : d.absolute;
        if (d.absolute > bound) ++c.overTolerance;
        if (d.absolute > c.maxAbsolute.absolute) c.maxAbsolute = d;
        if (d.relative > c.maxRelative.relative) c.maxRelative = d;
        if (settings.worstKept <= 0 || d.absolute == 0) return;
        if (c.worst.size() < std::size_t(settings.worstKept)) {
            c.worst.push_back(d);
            std::push_heap(c.worst.begin(), c.worst.end(), byExcess);
        } else if (d.excess > c.worst.front().excess) {
            std::pop_heap(c.worst.begin(), c.worst.end(), byExcess);
            c.worst.back() = d;
            std::push_heap(c.worst.begin(), c.worst.end(), byExcess);
        }
    };
    for (uint32_t row = 0; row < a.size; ++row) {
        const auto ca = a.rowColumns(row), cb = b.rowColumns(row);
        const auto va = a.rowValues(row), vb = b.rowValues(row);
        std::size_t p = 0, q = 0;
        while (p < ca.size() || q < cb.size()) {
            ++c.unionEntries;
            if (q == cb.size() || (p < ca.size() && ca[p] < cb[q])) {
                ++c.onlyInA;
                consider(row, ca[p], va[p], 0.0f);
                ++p;
            } else if (p == ca.size() || cb[q] < ca[p]) {
                ++c.onlyInB;
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

}  // namespace daisy
