// The settings sweep's errors against its reference (sweep_measure.h; bench/sweep.h says what
// they are).
#include "bench/sweep_measure.h"

#include <algorithm>
#include <cmath>
#include <span>

#include "image/exposure.h"
#include "image/image_io.h"
#include "spectral/color.h"

namespace daisy::sweep {
namespace {

struct Groups {
    std::vector<double> areas;
    std::vector<double> spectra;  // groups x m, area-weighted means
};

Groups groupByPatch(const Solution& s) {
    return {s.patches.areas, s.radiosity};
}

Groups groupBySourceTriangle(const Solution& s) {
    const std::size_t m = s.set.size();
    uint32_t triangles = 0;
    for (uint32_t t : s.patches.sourceTriangle)
        triangles = std::max(triangles, t + 1);
    Groups g{std::vector<double>(triangles, 0.0), std::vector<double>(triangles * m, 0.0)};
    for (std::size_t i = 0; i < s.patches.patchCount(); ++i) {
        const uint32_t t = s.patches.sourceTriangle[i];
        g.areas[t] += s.patches.areas[i];
        for (std::size_t k = 0; k < m; ++k)
            g.spectra[t * m + k] += s.patches.areas[i] * s.radiosity[i * m + k];
    }
    for (uint32_t t = 0; t < triangles; ++t)
        for (std::size_t k = 0; k < m && g.areas[t] > 0; ++k)
            g.spectra[t * m + k] /= g.areas[t];
    return g;
}

// The m x mr matrix that samples the reference's spectra on `set` as emission is sampled
// (spectral/spectrum.h): row k holds the hat-weighted mean of the reference's piecewise-
// linear reconstruction over set's hat k, integral h_k g_j / integral h_k, both over the
// reference's domain (numerically, 0.05 nm steps). The identity when the sets are equal. A
// hat wholly outside the reference's domain (daisyriot's 350 nm against a reference without
// UV samples) has nothing to compare with: its row is NaN.
std::vector<double> projectionOnto(const WavelengthSet& set, const WavelengthSet& reference) {
    const std::size_t m = set.size(), mr = reference.size();
    std::vector<double> p(m * mr, 0.0);
    if (set.wavelengthsNm() == reference.wavelengthsNm()) {
        for (std::size_t k = 0; k < m; ++k)
            p[k * mr + k] = 1;
        return p;
    }
    constexpr double kStepNm = 0.05;
    for (std::size_t k = 0; k < m; ++k) {
        auto [first, last] = set.hatSupportNm(k);
        first = std::max(first, reference.domainStartNm());
        last = std::min(last, reference.domainEndNm());
        double weight = 0;
        for (double nm = first + kStepNm / 2; nm < last; nm += kStepNm) {
            const double h = set.hat(k, nm);
            weight += h;
            for (std::size_t j = 0; j < mr; ++j)
                p[k * mr + j] += h * reference.hat(j, nm);
        }
        for (std::size_t j = 0; j < mr; ++j)
            p[k * mr + j] = weight > 0 ? p[k * mr + j] / weight : NAN;
    }
    return p;
}

// Lab of every pixel as displayed: the reference's exposure, 8-bit sRGB, decoded under D65.
std::vector<Lab> displayedLab(const Image& xyz, double exposureScale) {
    const std::vector<uint8_t> srgb = toSrgb8(xyzToLinearSrgb(xyz, exposureScale));
    std::vector<Lab> lab(srgb.size() / 3);
    for (std::size_t p = 0; p < lab.size(); ++p)
        lab[p] = srgb8ToLab({srgb[p * 3], srgb[p * 3 + 1], srgb[p * 3 + 2]});
    return lab;
}

}  // namespace

void measure(const Solution& solution, const Solution& reference, double exposureScale,
             SweepRow& row) {
    const bool samePatches = solution.patches.patchCount() == reference.patches.patchCount() &&
        solution.patches.sourceTriangle == reference.patches.sourceTriangle;
    row.errorLevel = samePatches ? "patch" : "triangle";
    const auto groups = [&](const Solution& s) {
        return samePatches ? groupByPatch(s) : groupBySourceTriangle(s);
    };
    const Groups mine = groups(solution), theirs = groups(reference);
    const WavelengthSet& set = solution.set;
    const std::size_t m = set.size(), mr = reference.set.size();
    double diffB = 0, normB = 0, diffY = 0, normY = 0;
    const std::vector<double> projection = projectionOnto(set, reference.set);
    std::vector<double> resampled(m);
    for (std::size_t g = 0; g < mine.areas.size(); ++g) {
        const double* b = mine.spectra.data() + g * m;
        const double* r = theirs.spectra.data() + g * mr;
        for (std::size_t k = 0; k < m; ++k) {
            resampled[k] = 0;
            for (std::size_t j = 0; j < mr; ++j)
                resampled[k] += projection[k * mr + j] * r[j];
            if (std::isnan(projection[k * mr])) continue;  // outside the reference's domain
            const double w = mine.areas[g] * set.binWidthNm(k);
            diffB += w * (b[k] - resampled[k]) * (b[k] - resampled[k]);
            normB += w * resampled[k] * resampled[k];
        }
        const double y = set.toXyz(std::span<const double>(b, m))[1];
        const double yr = reference.set.toXyz(std::span<const double>(r, mr))[1];
        diffY += mine.areas[g] * (y - yr) * (y - yr);
        normY += mine.areas[g] * yr * yr;
    }
    row.relativeRmsB = normB > 0 ? std::sqrt(diffB / normB) : NAN;
    row.relativeRmsY = normY > 0 ? std::sqrt(diffY / normY) : NAN;

    const std::vector<Lab> a = displayedLab(solution.xyz, exposureScale),
                           b = displayedLab(reference.xyz, exposureScale);
    std::vector<double> deltas(a.size());
    double sum = 0;
    for (std::size_t p = 0; p < a.size(); ++p) {
        deltas[p] = deltaE2000(a[p], b[p]);
        sum += deltas[p];
    }
    row.meanDeltaE = deltas.empty() ? NAN : sum / deltas.size();
    if (!deltas.empty()) {
        const std::size_t at = std::min(deltas.size() - 1, deltas.size() * 95 / 100);
        std::nth_element(deltas.begin(), deltas.begin() + at, deltas.end());
        row.p95DeltaE = deltas[at];
    }
}

}  // namespace daisy::sweep
