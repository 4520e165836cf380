#include "radiosity/energy.h"

#include <cmath>

namespace daisy {

double EnergyBalance::imbalance() const {
    return emitted > 0 ? (emitted - absorbed - escaped) / emitted : 0;
}

EnergyBalance computeEnergyBalance(const RadiositySystem& system, std::span<const double> rowSums,
                                   std::span<const double> radiosity,
                                   std::span<const double> gathered) {
    const std::size_t m = system.wavelengthCount;
    const std::vector<double>& w = system.binWidthsNm;
    EnergyBalance balance;
    balance.emittedPerSample.assign(m, 0);
    balance.escapedPerSample.assign(m, 0);
    balance.absorbedPerSample.assign(m, 0);
    balance.convertedInPerSample.assign(m, 0);
    for (uint32_t i = 0; i < system.patchCount; ++i) {
        const MaterialOperator& op = system.operators[system.patchOperator[i]];
        const double area = system.areas[i];
        const double* e = system.emissionRow(i);
        const double* b = radiosity.data() + std::size_t(i) * m;
        const double* g = gathered.data() + std::size_t(i) * m;
        const double open = 1 - rowSums[i];
        for (std::size_t k = 0; k < m; ++k) {
            balance.emittedPerSample[k] += area * w[k] * e[k];
            balance.escapedPerSample[k] += area * w[k] * b[k] * open;
            // Power leaving sample k's incident light: reflected at k, or moved to o > k.
            double leaves = 0;
            for (std::size_t o = 0; o < m; ++o) {
                const double moved = area * w[o] * op.matrix(o, k) * g[k];
                leaves += moved;
                if (o != k) {
                    balance.converted += moved;
                    balance.convertedInPerSample[o] += moved;
                } else {
                    balance.reflected += moved;
                }
            }
            const double incident = area * w[k] * g[k];
            balance.incident += incident;
            balance.absorbedPerSample[k] += incident - leaves;
        }
    }
    for (std::size_t k = 0; k < m; ++k) {
        balance.emitted += balance.emittedPerSample[k];
        balance.escaped += balance.escapedPerSample[k];
        balance.absorbed += balance.absorbedPerSample[k];
    }
    return balance;
}

}  // namespace daisy
