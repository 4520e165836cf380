// The gather kernels (radiosity/gather_kernels.h) against the plain sum they replace,
// acc_k += sum_p F_p B_{c_p, k}, for every wavelength count with its own kernel (the default 35
// included) and a few without: equal up to summation order and FMA rounding, bounded
// by n eps sum |F B| (Higham 2002, "Accuracy and Stability of Numerical Algorithms", eq. 4.4)
// in double, and by the mixed-precision bound (runs of 64 float products, ~16 x 2^-24) for B read
// as float.
#include "radiosity/gather_kernels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "shared/rng.h"

namespace daisy {
namespace {

template <typename T>
void checkKernel(std::size_t m, double relative) {
    constexpr uint32_t kColumns = 97;
    constexpr uint64_t kEntries = 301;  // not a multiple of 4: the kernels' remainder loops run
    std::vector<uint32_t> columns(kEntries);
    std::vector<float> values(kEntries);
    std::vector<T> radiosity(std::size_t(kColumns) * m);
    uint32_t state = 12345;
    const auto next = [&] {
        state = shared::pcgHash(state);
        return float(state >> 8) / float(1u << 24);
    };
    for (uint64_t p = 0; p < kEntries; ++p) {
        columns[p] = uint32_t(next() * kColumns) % kColumns;
        values[p] = next();
    }
    for (T& b : radiosity)
        b = T(next() * 10.0f);
    std::vector<double> acc(m), exact(m), scale(m);
    for (std::size_t k = 0; k < m; ++k)
        acc[k] = exact[k] = 0.25 * double(k);
    const uint64_t begin = 3;  // a run inside the row, as the solvers pass it
    for (uint64_t p = begin; p < kEntries; ++p) {
        for (std::size_t k = 0; k < m; ++k) {
            const double term = double(values[p]) * double(radiosity[columns[p] * m + k]);
            exact[k] += term;
            scale[k] += std::fabs(term);
        }
    }
    accumulateFor<T>(m)(columns.data(), values.data(), begin, kEntries, radiosity.data(), m,
                        acc.data());
    for (std::size_t k = 0; k < m; ++k)
        ASSERT_NEAR(acc[k], exact[k], relative * scale[k] + 1e-300) << "m " << m << ", k " << k;
}

TEST(GatherKernels, EveryWavelengthCountMatchesThePlainSum) {
    for (std::size_t m : {1, 2, 3, 4, 5, 7, 8, 12, 16, 17, 20, 24, 28, 31, 32, 35, 36, 40, 48}) {
        checkKernel<double>(m, 301 * 2.3e-16);  // n eps, n = the entries summed
        checkKernel<float>(m, 2e-6);
    }
}

}  // namespace
}  // namespace daisy
