#pragma once
// CIE reference data from CIE 015:2018 (Colorimetry, 4th edition): the CIE 1931 2-degree
// colour-matching functions at 1 nm and the relative spectral power of illuminants A, D50, D65
// and F1-F12. The definitions are generated into cie_tables.cpp by tools/make_cie_tables.py from
// assets/reference/*.csv, values exactly as published.
#include <algorithm>
#include <array>
#include <cstddef>
#include <span>
#include <string_view>

namespace daisy {

inline constexpr int kCieCmfFirstNm = 360;
inline constexpr int kCieCmfLastNm = 830;
inline constexpr int kCieCmfCount = kCieCmfLastNm - kCieCmfFirstNm + 1;

// {xbar, ybar, zbar} at (kCieCmfFirstNm + k) nm; dimensionless. Zero outside the table.
extern const std::array<std::array<double, 3>, kCieCmfCount> kCie1931Cmf;

// One illuminant: values[k] is the relative spectral power at firstNm + k * stepNm, as the CIE
// tabulates it (A, D50, D65: 100 at 560 nm; F1-F12 on their own relative scale).
struct CieIlluminantTable {
    std::string_view name;
    double firstNm;
    double stepNm;
    std::span<const double> values;
};

// A, D50, D65, F1..F12, in that order.
extern const std::array<CieIlluminantTable, 15> kCieIlluminants;

// The illuminant called `name` (exact spelling), or nullptr.
inline const CieIlluminantTable* findCieIlluminant(std::string_view name) {
    for (const CieIlluminantTable& table : kCieIlluminants) {
        if (table.name == name) return &table;
    }
    return nullptr;
}

// The table interpolated linearly at `nm`; 0 outside it.
inline double evaluateCieIlluminant(const CieIlluminantTable& table, double nm) {
    const double position = (nm - table.firstNm) / table.stepNm;
    const double last = double(table.values.size() - 1);
    if (!(position >= 0 && position <= last)) return 0;
    const std::size_t i = std::min(std::size_t(position), table.values.size() - 2);
    const double t = position - double(i);
    return table.values[i] + t * (table.values[i + 1] - table.values[i]);
}

}  // namespace daisy
