#include "radiosity/gather_kernels.h"

#include "core/cpu_isa.h"

#include <algorithm>
#include <type_traits>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace daisy {
namespace {

template <typename T, std::size_t kM>
[[gnu::always_inline]] inline void accumulateBody(const uint32_t* columns, const float* values,
                                                  uint64_t begin, uint64_t end, const T* radiosity,
                                                  double* acc) {
    double local[kM];
    for (std::size_t k = 0; k < kM; ++k)
        local[k] = acc[k];
    for (uint64_t p = begin; p < end; ++p) {
        const double f = values[p];
        const T* b = radiosity + std::size_t(columns[p]) * kM;
        for (std::size_t k = 0; k < kM; ++k)
            local[k] += f * double(b[k]);
    }
    for (std::size_t k = 0; k < kM; ++k)
        acc[k] = local[k];
}

template <typename T, std::size_t kM>
void accumulateFixed(const uint32_t* columns, const float* values, uint64_t begin, uint64_t end,
                     const T* radiosity, std::size_t, double* acc) {
    accumulateBody<T, kM>(columns, values, begin, end, radiosity, acc);
}

#if defined(__x86_64__) && defined(__GNUC__)
#define DAISY_SOLVER_X86_VARIANTS 1
// Hand-vectorised variants, chosen at run time (bestAccumulate, by cpuIsa(): core/cpu_isa.h): one
// vector register per 8 (or 4) wavelengths, and four independent sums (entries p, p+1, p+2, p+3
// in turn) so consecutive fused multiply-adds do not wait on each other's latency; the sums are
// added at the end in a fixed order. Rounding differs from the plain loop (FMA, another order)
// and between the AVX2 and AVX-512 variants, but not with the thread count: a row's entries are
// always summed the same way.
inline __attribute__((target("avx512f"))) __m512d load8(const double* p) {
    return _mm512_loadu_pd(p);
}
inline __attribute__((target("avx512f"))) __m512d load8(const float* p) {
    // The zero-masked form: GCC 12 warns about the undefined source of _mm512_cvtps_pd.
    return _mm512_maskz_cvtps_pd(__mmask8(0xFF), _mm256_loadu_ps(p));
}
template <typename T, std::size_t kM>
__attribute__((target("avx512f"))) void accumulateAvx512(const uint32_t* columns,
                                                         const float* values, uint64_t begin,
                                                         uint64_t end, const T* radiosity,
                                                         std::size_t, double* acc) {
    constexpr std::size_t kV = kM / 8;
    __m512d sum[4][kV];
    for (std::size_t v = 0; v < kV; ++v) {
        sum[0][v] = _mm512_loadu_pd(acc + 8 * v);
        sum[1][v] = sum[2][v] = sum[3][v] = _mm512_setzero_pd();
    }
    uint64_t p = begin;
    for (; p + 4 <= end; p += 4) {
        for (std::size_t u = 0; u < 4; ++u) {
            if (p + u + kPrefetchAhead < end) {
                prefetchRow(radiosity + std::size_t(columns[p + u + kPrefetchAhead]) * kM, kM);
            }
            const __m512d f = _mm512_set1_pd(values[p + u]);
            const T* b = radiosity + std::size_t(columns[p + u]) * kM;
            for (std::size_t v = 0; v < kV; ++v)
                sum[u][v] = _mm512_fmadd_pd(f, load8(b + 8 * v), sum[u][v]);
        }
    }
    for (; p < end; ++p) {
        const __m512d f = _mm512_set1_pd(values[p]);
        const T* b = radiosity + std::size_t(columns[p]) * kM;
        for (std::size_t v = 0; v < kV; ++v)
            sum[0][v] = _mm512_fmadd_pd(f, load8(b + 8 * v), sum[0][v]);
    }
    for (std::size_t v = 0; v < kV; ++v) {
        const __m512d total =
            _mm512_add_pd(_mm512_add_pd(sum[0][v], sum[1][v]), _mm512_add_pd(sum[2][v], sum[3][v]));
        _mm512_storeu_pd(acc + 8 * v, total);
    }
}

inline __attribute__((target("avx2,fma"))) __m256d load4(const double* p) {
    return _mm256_loadu_pd(p);
}
inline __attribute__((target("avx2,fma"))) __m256d load4(const float* p) {
    return _mm256_cvtps_pd(_mm_loadu_ps(p));
}
template <typename T, std::size_t kM>
__attribute__((target("avx2,fma"))) void accumulateAvx2(const uint32_t* columns,
                                                        const float* values, uint64_t begin,
                                                        uint64_t end, const T* radiosity,
                                                        std::size_t, double* acc) {
    constexpr std::size_t kV = kM / 4;
    __m256d sum[4][kV];
    for (std::size_t v = 0; v < kV; ++v) {
        sum[0][v] = _mm256_loadu_pd(acc + 4 * v);
        sum[1][v] = sum[2][v] = sum[3][v] = _mm256_setzero_pd();
    }
    uint64_t p = begin;
    for (; p + 4 <= end; p += 4) {
        for (std::size_t u = 0; u < 4; ++u) {
            if (p + u + kPrefetchAhead < end) {
                prefetchRow(radiosity + std::size_t(columns[p + u + kPrefetchAhead]) * kM, kM);
            }
            const __m256d f = _mm256_set1_pd(values[p + u]);
            const T* b = radiosity + std::size_t(columns[p + u]) * kM;
            for (std::size_t v = 0; v < kV; ++v)
                sum[u][v] = _mm256_fmadd_pd(f, load4(b + 4 * v), sum[u][v]);
        }
    }
    for (; p < end; ++p) {
        const __m256d f = _mm256_set1_pd(values[p]);
        const T* b = radiosity + std::size_t(columns[p]) * kM;
        for (std::size_t v = 0; v < kV; ++v)
            sum[0][v] = _mm256_fmadd_pd(f, load4(b + 4 * v), sum[0][v]);
    }
    for (std::size_t v = 0; v < kV; ++v) {
        const __m256d total =
            _mm256_add_pd(_mm256_add_pd(sum[0][v], sum[1][v]), _mm256_add_pd(sum[2][v], sum[3][v]));
        _mm256_storeu_pd(acc + 4 * v, total);
    }
}
// Counts that are not a multiple of the vector width (the default 35 wavelengths):
// kM / 8 (or / 4) vector sums plus a scalar tail of kM % 8 (or % 4) sums in one pass over the
// entries. One set of sums only: with kM >= 16 there are already >= 2 independent FMA chains an
// entry, and four sets of 5+ vectors would spill the 16 (AVX2) registers.
template <typename T, std::size_t kM>
__attribute__((target("avx512f"))) void accumulateAvx512Tail(const uint32_t* columns,
                                                             const float* values, uint64_t begin,
                                                             uint64_t end, const T* radiosity,
                                                             std::size_t, double* acc) {
    constexpr std::size_t kV = kM / 8;
    constexpr std::size_t kR = kM % 8;
    __m512d sum[kV];
    double tail[kR > 0 ? kR : 1];
    for (std::size_t v = 0; v < kV; ++v)
        sum[v] = _mm512_loadu_pd(acc + 8 * v);
    for (std::size_t r = 0; r < kR; ++r)
        tail[r] = acc[8 * kV + r];
    for (uint64_t p = begin; p < end; ++p) {
        if (p + kPrefetchAhead < end) {
            prefetchRow(radiosity + std::size_t(columns[p + kPrefetchAhead]) * kM, kM);
        }
        const double fd = values[p];
        const __m512d f = _mm512_set1_pd(fd);
        const T* b = radiosity + std::size_t(columns[p]) * kM;
        for (std::size_t v = 0; v < kV; ++v)
            sum[v] = _mm512_fmadd_pd(f, load8(b + 8 * v), sum[v]);
        for (std::size_t r = 0; r < kR; ++r)
            tail[r] += fd * double(b[8 * kV + r]);
    }
    for (std::size_t v = 0; v < kV; ++v)
        _mm512_storeu_pd(acc + 8 * v, sum[v]);
    for (std::size_t r = 0; r < kR; ++r)
        acc[8 * kV + r] = tail[r];
}

template <typename T, std::size_t kM>
__attribute__((target("avx2,fma"))) void accumulateAvx2Tail(const uint32_t* columns,
                                                            const float* values, uint64_t begin,
                                                            uint64_t end, const T* radiosity,
                                                            std::size_t, double* acc) {
    constexpr std::size_t kV = kM / 4;
    constexpr std::size_t kR = kM % 4;
    __m256d sum[kV];
    double tail[kR > 0 ? kR : 1];
    for (std::size_t v = 0; v < kV; ++v)
        sum[v] = _mm256_loadu_pd(acc + 4 * v);
    for (std::size_t r = 0; r < kR; ++r)
        tail[r] = acc[4 * kV + r];
    for (uint64_t p = begin; p < end; ++p) {
        if (p + kPrefetchAhead < end) {
            prefetchRow(radiosity + std::size_t(columns[p + kPrefetchAhead]) * kM, kM);
        }
        const double fd = values[p];
        const __m256d f = _mm256_set1_pd(fd);
        const T* b = radiosity + std::size_t(columns[p]) * kM;
        for (std::size_t v = 0; v < kV; ++v)
            sum[v] = _mm256_fmadd_pd(f, load4(b + 4 * v), sum[v]);
        for (std::size_t r = 0; r < kR; ++r)
            tail[r] += fd * double(b[4 * kV + r]);
    }
    for (std::size_t v = 0; v < kV; ++v)
        _mm256_storeu_pd(acc + 4 * v, sum[v]);
    for (std::size_t r = 0; r < kR; ++r)
        acc[4 * kV + r] = tail[r];
}

// Mixed precision (B read as float): the products are summed in float over runs of
// kFloatRunEntries entries (four interleaved sums of 16), each run then added to the double
// sums: one float FMA per 16 wavelengths and entry instead of two double FMAs and two
// conversions. A run's rounding error is below 16 x 2^-24 ~ 1e-6 relative in the worst case
// (Higham 2002, "Accuracy and Stability of Numerical Algorithms", eq. 4.4), ~1e-7 typically,
// which kMixedPrecisionMinTolerance keeps ten times under the tolerance.
constexpr uint64_t kFloatRunEntries = 64;

// Sets the SSE control register's flush-to-zero and denormals-are-zero bits for its lifetime.
// Spectra falling off steeply (emission 1e-40 W m^-2 nm^-1 far from a UV lamp's band) are float
// denormals, and every FMA touching one takes a microcode assist (~100 cycles): measured on the
// benchmark scene, it made the float gather slower than the double one. Zeroing values under
// 1.2e-38 changes nothing a radiometric tolerance can see.
class DenormalsAreZero {
public:
    DenormalsAreZero() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040); }
    ~DenormalsAreZero() { _mm_setcsr(saved_); }
    DenormalsAreZero(const DenormalsAreZero&) = delete;
    DenormalsAreZero& operator=(const DenormalsAreZero&) = delete;

private:
    unsigned saved_;
};

template <std::size_t kM>
__attribute__((target("avx512f"))) void accumulateAvx512Float(const uint32_t* columns,
                                                              const float* values, uint64_t begin,
                                                              uint64_t end, const float* radiosity,
                                                              std::size_t, double* acc) {
    constexpr std::size_t kV = kM / 16;
    const DenormalsAreZero denormalsAreZero;
    __m512d total[2 * kV];
    for (std::size_t v = 0; v < 2 * kV; ++v)
        total[v] = _mm512_loadu_pd(acc + 8 * v);
    uint64_t p = begin;
    while (p < end) {
        const uint64_t runEnd = std::min(end, p + kFloatRunEntries);
        __m512 sum[4][kV];
        for (std::size_t u = 0; u < 4; ++u)
            for (std::size_t v = 0; v < kV; ++v)
                sum[u][v] = _mm512_setzero_ps();
        for (; p + 4 <= runEnd; p += 4) {
            for (std::size_t u = 0; u < 4; ++u) {
                if (p + u + kPrefetchAhead < end) {
                    prefetchRow(radiosity + std::size_t(columns[p + u + kPrefetchAhead]) * kM, kM);
                }
                const __m512 f = _mm512_set1_ps(values[p + u]);
                const float* b = radiosity + std::size_t(columns[p + u]) * kM;
                for (std::size_t v = 0; v < kV; ++v)
                    sum[u][v] = _mm512_fmadd_ps(f, _mm512_loadu_ps(b + 16 * v), sum[u][v]);
            }
        }
        for (; p < runEnd; ++p) {
            const __m512 f = _mm512_set1_ps(values[p]);
            const float* b = radiosity + std::size_t(columns[p]) * kM;
            for (std::size_t v = 0; v < kV; ++v)
                sum[0][v] = _mm512_fmadd_ps(f, _mm512_loadu_ps(b + 16 * v), sum[0][v]);
        }
        for (std::size_t v = 0; v < kV; ++v) {
            const __m512 run = _mm512_add_ps(_mm512_add_ps(sum[0][v], sum[1][v]),
                                             _mm512_add_ps(sum[2][v], sum[3][v]));
            // Halves by zero-masked extracts: GCC 12 warns about the undefined upper part
            // in _mm512_castps512_ps256 / _mm512_extractf64x4_pd.
            const __m512d bits = _mm512_castps_pd(run);
            const __m256 low =
                _mm256_castpd_ps(_mm512_maskz_extractf64x4_pd(__mmask8(0xF), bits, 0));
            const __m256 high =
                _mm256_castpd_ps(_mm512_maskz_extractf64x4_pd(__mmask8(0xF), bits, 1));
            total[2 * v] = _mm512_add_pd(total[2 * v], _mm512_maskz_cvtps_pd(__mmask8(0xFF), low));
            total[2 * v + 1] =
                _mm512_add_pd(total[2 * v + 1], _mm512_maskz_cvtps_pd(__mmask8(0xFF), high));
        }
    }
    for (std::size_t v = 0; v < 2 * kV; ++v)
        _mm512_storeu_pd(acc + 8 * v, total[v]);
}

template <std::size_t kM>
__attribute__((target("avx2,fma"))) void accumulateAvx2Float(const uint32_t* columns,
                                                             const float* values, uint64_t begin,
                                                             uint64_t end, const float* radiosity,
                                                             std::size_t, double* acc) {
    constexpr std::size_t kV = kM / 8;
    const DenormalsAreZero denormalsAreZero;
    __m256d total[2 * kV];
    for (std::size_t v = 0; v < 2 * kV; ++v)
        total[v] = _mm256_loadu_pd(acc + 4 * v);
    uint64_t p = begin;
    while (p < end) {
        const uint64_t runEnd = std::min(end, p + kFloatRunEntries);
        __m256 sum[4][kV];
        for (std::size_t u = 0; u < 4; ++u)
            for (std::size_t v = 0; v < kV; ++v)
                sum[u][v] = _mm256_setzero_ps();
        for (; p + 4 <= runEnd; p += 4) {
            for (std::size_t u = 0; u < 4; ++u) {
                if (p + u + kPrefetchAhead < end) {
                    prefetchRow(radiosity + std::size_t(columns[p + u + kPrefetchAhead]) * kM, kM);
                }
                const __m256 f = _mm256_set1_ps(values[p + u]);
                const float* b = radiosity + std::size_t(columns[p + u]) * kM;
                for (std::size_t v = 0; v < kV; ++v)
                    sum[u][v] = _mm256_fmadd_ps(f, _mm256_loadu_ps(b + 8 * v), sum[u][v]);
            }
        }
        for (; p < runEnd; ++p) {
            const __m256 f = _mm256_set1_ps(values[p]);
            const float* b = radiosity + std::size_t(columns[p]) * kM;
            for (std::size_t v = 0; v < kV; ++v)
                sum[0][v] = _mm256_fmadd_ps(f, _mm256_loadu_ps(b + 8 * v), sum[0][v]);
        }
        for (std::size_t v = 0; v < kV; ++v) {
            const __m256 run = _mm256_add_ps(_mm256_add_ps(sum[0][v], sum[1][v]),
                                             _mm256_add_ps(sum[2][v], sum[3][v]));
            total[2 * v] =
                _mm256_add_pd(total[2 * v], _mm256_cvtps_pd(_mm256_castps256_ps128(run)));
            total[2 * v + 1] =
                _mm256_add_pd(total[2 * v + 1], _mm256_cvtps_pd(_mm256_extractf128_ps(run, 1)));
        }
    }
    for (std::size_t v = 0; v < 2 * kV; ++v)
        _mm256_storeu_pd(acc + 4 * v, total[v]);
}
#endif

template <typename T, std::size_t kM>
AccumulateFn<T> bestAccumulate() {
#ifdef DAISY_SOLVER_X86_VARIANTS
    if constexpr (std::is_same_v<T, float> && kM % 16 == 0) {
        if (cpuIsa() == CpuIsa::Avx512) return accumulateAvx512Float<kM>;
    }
    if constexpr (std::is_same_v<T, float> && kM % 8 == 0) {
        if (cpuIsa() >= CpuIsa::Avx2) return accumulateAvx2Float<kM>;
    }
    if constexpr (kM % 8 == 0) {
        if (cpuIsa() == CpuIsa::Avx512) return accumulateAvx512<T, kM>;
    }
    if constexpr (kM % 4 == 0) {
        if (cpuIsa() >= CpuIsa::Avx2) return accumulateAvx2<T, kM>;
    }
    if constexpr (kM >= 16 && kM % 8 != 0) {
        if (cpuIsa() == CpuIsa::Avx512) return accumulateAvx512Tail<T, kM>;
    }
    if constexpr (kM >= 16 && kM % 4 != 0) {
        if (cpuIsa() >= CpuIsa::Avx2) return accumulateAvx2Tail<T, kM>;
    }
#endif
    return accumulateFixed<T, kM>;
}

template <typename T>
void accumulateAny(const uint32_t* columns, const float* values, uint64_t begin, uint64_t end,
                   const T* radiosity, std::size_t m, double* acc) {
    for (uint64_t p = begin; p < end; ++p) {
        const double f = values[p];
        const T* b = radiosity + std::size_t(columns[p]) * m;
        for (std::size_t k = 0; k < m; ++k)
            acc[k] += f * double(b[k]);
    }
}

}  // namespace

template <typename T>
AccumulateFn<T> accumulateFor(std::size_t m) {
    switch (m) {
        case 1:
            return bestAccumulate<T, 1>();
        case 3:
            return bestAccumulate<T, 3>();
        case 4:
            return bestAccumulate<T, 4>();
        case 7:
            return bestAccumulate<T, 7>();
        case 8:
            return bestAccumulate<T, 8>();
        case 12:
            return bestAccumulate<T, 12>();
        case 16:
            return bestAccumulate<T, 16>();
        case 20:
            return bestAccumulate<T, 20>();
        case 24:
            return bestAccumulate<T, 24>();
        case 28:
            return bestAccumulate<T, 28>();
        case 31:
            return bestAccumulate<T, 31>();
        case 32:
            return bestAccumulate<T, 32>();
        case 35:  // the default `auto` wavelength set
            return bestAccumulate<T, 35>();
        case 36:
            return bestAccumulate<T, 36>();
        case 40:
            return bestAccumulate<T, 40>();
        case 48:
            return bestAccumulate<T, 48>();
        default:
            return accumulateAny<T>;
    }
}

template AccumulateFn<double> accumulateFor<double>(std::size_t m);
template AccumulateFn<float> accumulateFor<float>(std::size_t m);

}  // namespace daisy
