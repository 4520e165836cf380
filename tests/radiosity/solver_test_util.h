#pragma once
// Hand-built radiosity systems for the solver and energy tests.
#include <cstdint>
#include <random>
#include <vector>

#include "radiosity/radiosity_system.h"
#include "radiosity/sparse_matrix.h"

namespace daisy::solvertest {

// CSR from a dense row-major n x n matrix (zeros dropped).
inline SparseMatrix sparseFromDense(uint32_t n, const std::vector<double>& dense) {
    SparseMatrix f = SparseMatrix::zeros(n);
    f.rowOffsets.assign(n + 1, 0);
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < n; ++j) {
            if (dense[i * n + j] == 0) continue;
            f.columns.push_back(j);
            f.values.push_back(static_cast<float>(dense[i * n + j]));
        }
        f.rowOffsets[i + 1] = f.columns.size();
    }
    return f;
}

// The closed "furnace" enclosure of n equal patches: F_ij = 1 / (n - 1) for j != i, rows summing
// to exactly 1 when n - 1 is a power of two (the float is exact).
inline SparseMatrix furnaceMatrix(uint32_t n) {
    std::vector<double> dense(std::size_t(n) * n, 0);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < n; ++j)
            if (i != j) dense[i * n + j] = 1.0 / (n - 1);
    return sparseFromDense(n, dense);
}

inline MaterialOperator diagonalOperator(const std::vector<double>& rho) {
    MaterialOperator op;
    op.matrix.size = rho.size();
    op.matrix.values.assign(rho.size() * rho.size(), 0);
    for (std::size_t k = 0; k < rho.size(); ++k)
        op.matrix(k, k) = rho[k];
    finishOperator(op, std::vector<double>(rho.size(), 1.0));
    return op;
}

inline MaterialOperator matrixOperator(std::size_t m, const std::vector<double>& values) {
    MaterialOperator op;
    op.matrix.size = m;
    op.matrix.values = values;
    finishOperator(op, std::vector<double>(m, 1.0));
    return op;
}

// n patches, m unit-width samples, unit areas unless given, every patch on operator 0.
inline RadiositySystem makeSystem(uint32_t n, std::size_t m, std::vector<MaterialOperator> ops) {
    RadiositySystem system;
    system.patchCount = n;
    system.wavelengthCount = m;
    for (std::size_t k = 0; k < m; ++k)
        system.wavelengthsNm.push_back(400 + 50.0 * k);
    system.binWidthsNm.assign(m, 1.0);
    system.emission.assign(std::size_t(n) * m, 0);
    system.areas.assign(n, 1.0);
    system.patchOperator.assign(n, 0);
    system.operators = std::move(ops);
    return system;
}

// A random open enclosure obeying reciprocity: areas A_i in [0.5, 2], a symmetric coupling
// S_ij = S_ji, F_ij = S_ij / A_i scaled so every row sums to at most `maxRowSum`; about
// `density` of the pairs coupled. Three operators: diagonal, fluorescent (lower-triangular,
// power column sums < 1) and zero; random emission on a few patches.
inline std::pair<SparseMatrix, RadiositySystem> randomSystem(uint32_t n, std::size_t m,
                                                             double maxRowSum, double density,
                                                             uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<double> area(n);
    for (double& a : area)
        a = 0.5 + 1.5 * unit(rng);
    std::vector<double> s(std::size_t(n) * n, 0);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = i + 1; j < n; ++j)
            if (unit(rng) < density) s[i * n + j] = s[j * n + i] = unit(rng);
    double worst = 0;
    for (uint32_t i = 0; i < n; ++i) {
        double sum = 0;
        for (uint32_t j = 0; j < n; ++j)
            sum += s[i * n + j] / area[i];
        worst = std::max(worst, sum);
    }
    std::vector<double> dense(std::size_t(n) * n, 0);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < n; ++j)
            dense[i * n + j] = s[i * n + j] / area[i] * maxRowSum / worst;
    SparseMatrix f = sparseFromDense(n, dense);
    // Reciprocity for the stored floats: take F_ji from F_ij.
    for (uint32_t i = 0; i < n; ++i) {
        for (uint64_t p = f.rowOffsets[i]; p < f.rowOffsets[i + 1]; ++p) {
            const uint32_t j = f.columns[p];
            if (j <= i) continue;
            const double fji = double(f.values[p]) * area[i] / area[j];
            for (uint64_t q = f.rowOffsets[j]; q < f.rowOffsets[j + 1]; ++q)
                if (f.columns[q] == i) f.values[q] = static_cast<float>(fji);
        }
    }

    std::vector<double> rho(m), fluorescent(m * m, 0);
    for (std::size_t k = 0; k < m; ++k)
        rho[k] = 0.3 + 0.6 * unit(rng);
    for (std::size_t k = 0; k < m; ++k) {
        fluorescent[k * m + k] = 0.4 * unit(rng);
        double budget = 0.9 - fluorescent[k * m + k];
        for (std::size_t o = k + 1; o < m; ++o) {
            const double share = budget * unit(rng) / double(m - k);
            fluorescent[o * m + k] = share;
        }
    }
    RadiositySystem system = makeSystem(n, m,
                                        {diagonalOperator(rho), matrixOperator(m, fluorescent),
                                         diagonalOperator(std::vector<double>(m, 0.0))});
    system.areas = area;
    for (uint32_t i = 0; i < n; ++i) {
        system.patchOperator[i] = i % 7 == 3 ? 2 : (i % 3 == 1 ? 1 : 0);
        if (i % 5 == 0)
            for (std::size_t k = 0; k < m; ++k)
                system.emission[i * m + k] = unit(rng);
    }
    return {std::move(f), std::move(system)};
}

// Dense solve of (I - M F) B = E by Gaussian elimination with partial pivoting (the oracle).
inline std::vector<double> denseSolve(const SparseMatrix& f, const RadiositySystem& system) {
    const std::size_t n = system.patchCount, m = system.wavelengthCount, size = n * m;
    std::vector<double> a(size * size, 0), x = system.emission;
    for (std::size_t i = 0; i < n; ++i) {
        const MaterialOperator& op = system.operators[system.patchOperator[i]];
        for (std::size_t o = 0; o < m; ++o) {
            const std::size_t row = i * m + o;
            a[row * size + row] += 1;
            for (uint64_t p = f.rowOffsets[i]; p < f.rowOffsets[i + 1]; ++p)
                for (std::size_t k = 0; k < m; ++k)
                    a[row * size + f.columns[p] * m + k] -= op.matrix(o, k) * f.values[p];
        }
    }
    for (std::size_t c = 0; c < size; ++c) {
        std::size_t pivot = c;
        for (std::size_t r = c + 1; r < size; ++r)
            if (std::abs(a[r * size + c]) > std::abs(a[pivot * size + c])) pivot = r;
        for (std::size_t k = 0; k < size; ++k)
            std::swap(a[c * size + k], a[pivot * size + k]);
        std::swap(x[c], x[pivot]);
        for (std::size_t r = c + 1; r < size; ++r) {
            const double factor = a[r * size + c] / a[c * size + c];
            for (std::size_t k = c; k < size; ++k)
                a[r * size + k] -= factor * a[c * size + k];
            x[r] -= factor * x[c];
        }
    }
    for (std::size_t c = size; c-- > 0;) {
        for (std::size_t k = c + 1; k < size; ++k)
            x[c] -= a[c * size + k] * x[k];
        x[c] /= a[c * size + c];
    }
    return x;
}

}  // namespace daisy::solvertest
