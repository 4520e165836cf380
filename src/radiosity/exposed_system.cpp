#include "radiosity/exposed_system.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "core/check.h"

namespace daisy {

namespace {

constexpr double kSteps = 64;  // exposed shares are rounded up to 1/64

}  // namespace

std::vector<double> unburiedRowSums(const Transport& transport, std::span<const double> areas,
                                    std::span<const float> exposure) {
    const std::span<const double> sums = transport.rowSums();
    DAISY_CHECK(exposure.size() == sums.size() && areas.size() == sums.size());
    std::vector<double> out(sums.begin(), sums.end());
    std::vector<TransportEntry> row;
    for (uint32_t j = 0; j < out.size(); ++j) {
        if (exposure[j] > 0) continue;
        transport.row(j, row);
        for (const TransportEntry& entry : row)
            out[entry.patch] -= areas[j] * double(entry.factor) / areas[entry.patch];
    }
    for (double& sum : out)
        sum = std::max(sum, 0.0);
    return out;
}

ExposedSystem exposedSystem(const RadiositySystem& system, std::span<const float> exposure,
                            std::span<const double> rowSums) {
    const std::size_t n = system.patchCount;
    DAISY_CHECK(exposure.size() == n && rowSums.size() == n);
    ExposedSystem out;
    out.phi.assign(n, 1.0);
    out.rowSums.assign(rowSums.begin(), rowSums.end());
    // Per patch: max(phi, rowsum) in 1/64, rounded up; 0 = keep; kBuried: reflect nothing.
    constexpr int kBuried = -1;
    std::vector<int> steps(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const double phi = exposure[i];
        if (system.operators[system.patchOperator[i]].isZero) continue;
        if (phi == 0) {  // inside an object: what reaches it stays there
            steps[i] = kBuried;
            out.changed = true;
            continue;
        }
        if (!(phi < 1) || !(rowSums[i] > 0)) continue;
        const int step = int(std::ceil(std::max(phi, std::min(rowSums[i], 1.0)) * kSteps));
        if (step >= int(kSteps)) continue;
        steps[i] = step;
        out.phi[i] = phi;
        out.changed = true;
    }
    if (!out.changed) return out;
    out.system = system;
    std::map<std::pair<uint32_t, int>, uint32_t> copies;
    for (std::size_t i = 0; i < n; ++i) {
        if (steps[i] == 0) continue;
        const uint32_t op = system.patchOperator[i];
        const auto [it, added] =
            copies.emplace(std::pair{op, steps[i]}, uint32_t(out.system.operators.size()));
        const double scale = steps[i] == kBuried ? 0.0 : kSteps / steps[i];
        if (added) {
            MaterialOperator scaled = system.operators[op];
            for (double& v : scaled.matrix.values)
                v *= scale;
            finishOperator(scaled, system.binWidthsNm);
            out.system.operators.push_back(std::move(scaled));
        }
        out.system.patchOperator[i] = it->second;
        if (steps[i] == kBuried) continue;
        out.system.areas[i] = system.areas[i] / scale;
        out.rowSums[i] = rowSums[i] * scale;
    }
    return out;
}

namespace {

// radiosity_ik = E_ik + convert(phi_i, radiosity_ik - E_ik) for every patch with phi_i < 1.
template <typename Convert>
void convertReflected(const RadiositySystem& system, std::span<const double> phi,
                      std::span<double> radiosity, Convert convert) {
    const std::size_t m = system.wavelengthCount;
    for (std::size_t i = 0; i < phi.size(); ++i) {
        if (phi[i] == 1.0) continue;
        const double* e = system.emissionRow(uint32_t(i));
        for (std::size_t k = 0; k < m; ++k)
            radiosity[i * m + k] = e[k] + convert(phi[i], radiosity[i * m + k] - e[k]);
    }
}

}  // namespace

void exposedToWholePatch(const RadiositySystem& system, std::span<const double> phi,
                         std::span<double> radiosity) {
    convertReflected(system, phi, radiosity, [](double p, double r) { return p * r; });
}

void wholePatchToExposed(const RadiositySystem& system, std::span<const double> phi,
                         std::span<double> radiosity) {
    convertReflected(system, phi, radiosity, [](double p, double r) { return r / p; });
}

}  // namespace daisy
