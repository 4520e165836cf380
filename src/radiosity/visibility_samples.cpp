#include "radiosity/visibility_samples.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <vector>

#include "core/cpu_isa.h"
#include "shared/rng.h"
#include "shared/sampling.h"

// The hot loops below vectorise across samples; with AVX2 (per-lane variable shifts for the PCG
// hash) they run about twice as fast, so x86-64 builds carry an AVX2 variant of each entry point,
// used when cpuIsa() allows it (core/cpu_isa.h: DAISY_ISA=sse2 runs the baseline one on any
// machine). No FMA is enabled, so both variants round exactly like the scalar shared code.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define DAISY_SAMPLES_AVX2 1
#endif

namespace daisy {
namespace {

using shared::PatchGeometry;
using shared::vec3;

constexpr int kBlock = 16;  // samples per vectorised block
constexpr int kSmallBlock = 4;  // the block of the default 4 rays a pair (no 12 lanes wasted)

// Points q = first .. first + count - 1 (count <= kLanes) of
// shared::stratifiedPointOnTriangle(seed, q, total, t), written as x[q - first], ...: the same
// operations in the same order as the shared code, laid out so the loops over samples
// vectorise. Inlined into each of the cloned entry points below, so it takes their target.
template <int kLanes>
[[gnu::always_inline]] inline void stratifiedBlockOf(uint32_t seed, int first, int count, int total,
                                                     const PatchGeometry& t, float* x, float* y,
                                                     float* z) {
    const int levels = shared::stratificationLevels(total);
    const uint32_t scramble = shared::pcgHash(seed);
    const uint32_t jitterKey = shared::pcgHash(shared::pcgHash(seed + 0x68bc21ebu));
    float ax[kLanes], ay[kLanes], az[kLanes], bx[kLanes], by[kLanes], bz[kLanes];
    float cx[kLanes], cy[kLanes], cz[kLanes];
    for (int k = 0; k < kLanes; ++k) {
        ax[k] = t.a.x, ay[k] = t.a.y, az[k] = t.a.z;
        bx[k] = t.b.x, by[k] = t.b.y, bz[k] = t.b.z;
        cx[k] = t.c.x, cy[k] = t.c.y, cz[k] = t.c.z;
    }
    // selectSubTriangle(d, a, b, c) per lane: child 0, 1, 2 keep corner a, b, c; 3 is the
    // middle one. The choice is a bitwise blend of the candidates, so the values are exactly
    // the selected floats (no arithmetic on the not-chosen ones) and the loop vectorises.
    const auto bits = [](float f) { return std::bit_cast<uint32_t>(f); };
    const auto pick = [&](uint32_t m0, uint32_t m1, uint32_t m2, uint32_t m3, float v0, float v1,
                          float v2, float v3) {
        return std::bit_cast<float>((bits(v0) & m0) | (bits(v1) & m1) | (bits(v2) & m2) |
                                    (bits(v3) & m3));
    };
    for (int l = 0; l < levels; ++l) {
        const uint32_t shift = uint32_t(2 * l);
        for (int k = 0; k < kLanes; ++k) {
            const uint32_t q = uint32_t(first + k);
            const uint32_t d = ((q >> shift) ^ (scramble >> shift)) & 3u;
            const uint32_t m0 = 0u - uint32_t(d == 0u), m1 = 0u - uint32_t(d == 1u);
            const uint32_t m2 = 0u - uint32_t(d == 2u), m3 = 0u - uint32_t(d == 3u);
            const float abx = (ax[k] + bx[k]) * 0.5f, aby = (ay[k] + by[k]) * 0.5f,
                        abz = (az[k] + bz[k]) * 0.5f;
            const float bcx = (bx[k] + cx[k]) * 0.5f, bcy = (by[k] + cy[k]) * 0.5f,
                        bcz = (bz[k] + cz[k]) * 0.5f;
            const float cax = (cx[k] + ax[k]) * 0.5f, cay = (cy[k] + ay[k]) * 0.5f,
                        caz = (cz[k] + az[k]) * 0.5f;
            const float nax = pick(m0, m1, m2, m3, ax[k], abx, cax, bcx);
            const float nay = pick(m0, m1, m2, m3, ay[k], aby, cay, bcy);
            const float naz = pick(m0, m1, m2, m3, az[k], abz, caz, bcz);
            const float nbx = pick(m0, m1, m2, m3, abx, bx[k], bcx, cax);
            const float nby = pick(m0, m1, m2, m3, aby, by[k], bcy, cay);
            const float nbz = pick(m0, m1, m2, m3, abz, bz[k], bcz, caz);
            const float ncx = pick(m0, m1, m2, m3, cax, bcx, cx[k], abx);
            const float ncy = pick(m0, m1, m2, m3, cay, bcy, cy[k], aby);
            const float ncz = pick(m0, m1, m2, m3, caz, bcz, cz[k], abz);
            ax[k] = nax, ay[k] = nay, az[k] = naz;
            bx[k] = nbx, by[k] = nby, bz[k] = nbz;
            cx[k] = ncx, cy[k] = ncy, cz[k] = ncz;
        }
    }
    float ux[kLanes], uy[kLanes], su[kLanes];
    for (int k = 0; k < kLanes; ++k) {
        const uint32_t q = uint32_t(first + k);
        ux[k] = shared::uintToUnitFloat(shared::pcgHash((2u * q) ^ jitterKey));
        uy[k] = shared::uintToUnitFloat(shared::pcgHash((2u * q + 1u) ^ jitterKey));
    }
    // Vectorises with -fno-math-errno (the library's flag); sqrt is correctly rounded either way.
    for (int k = 0; k < kLanes; ++k)
        su[k] = shared::sqrt(ux[k]);
    float px[kLanes], py[kLanes], pz[kLanes];
    for (int k = 0; k < kLanes; ++k) {
        // uniformPointOnTriangle: a (1 - su) + b (su (1 - u.y)) + c (su u.y), su = sqrt(u.x).
        const float wa = 1.0f - su[k], wb = su[k] * (1.0f - uy[k]), wc = su[k] * uy[k];
        px[k] = ax[k] * wa + bx[k] * wb + cx[k] * wc;
        py[k] = ay[k] * wa + by[k] * wb + cy[k] * wc;
        pz[k] = az[k] * wa + bz[k] * wb + cz[k] * wc;
    }
    std::copy(px, px + count, x);
    std::copy(py, py + count, y);
    std::copy(pz, pz + count, z);
}

// Segments pi[k] -> pj[k] trimmed `clearance` off both patch planes, and their kernel weights
// (shadowSegments' contract).
[[gnu::always_inline]] inline void trimSegmentsOf(int count, const float* xi, const float* yi,
                                                  const float* zi, const float* xj, const float* yj,
                                                  const float* zj, vec3 ni, vec3 nj,
                                                  float clearance, float* __restrict ox,
                                                  float* __restrict oy, float* __restrict oz,
                                                  float* __restrict ex, float* __restrict ey,
                                                  float* __restrict ez, float* __restrict weight) {
    for (int k = 0; k < count; ++k) {
        const float dx = xj[k] - xi[k], dy = yj[k] - yi[k], dz = zj[k] - zi[k];
        const float cosI = ni.x * dx + ni.y * dy + ni.z * dz;
        const float cosJ = -(nj.x * dx + nj.y * dy + nj.z * dz);
        const float leave = std::fabs(cosI);
        const float arrive = std::fabs(cosJ);
        const float r2 = dx * dx + dy * dy + dz * dz;
        weight[k] = r2 > 0.0f && cosI > 0.0f && cosJ > 0.0f ? (cosI / r2) * (cosJ / r2) : 0.0f;
        float t0 = clearance / leave;  // +inf when leave = 0: empty below
        float t1 = 1.0f - clearance / arrive;
        if (!(t0 < t1)) t0 = t1 = 0.0f;
        ox[k] = xi[k] + dx * t0;
        oy[k] = yi[k] + dy * t0;
        oz[k] = zi[k] + dz * t0;
        ex[k] = xi[k] + dx * t1;
        ey[k] = yi[k] + dy * t1;
        ez[k] = zi[k] + dz * t1;
    }
}

// The entry points, once per target: the bodies above inlined into each take its instructions.
struct SampleKernels {
    void (*block)(uint32_t seed, int first, int count, int total, const PatchGeometry& t, float* x,
                  float* y, float* z);
    void (*smallBlock)(uint32_t seed, int count, const PatchGeometry& t, float* x, float* y,
                       float* z);
    void (*trim)(int count, const float* xi, const float* yi, const float* zi, const float* xj,
                 const float* yj, const float* zj, vec3 ni, vec3 nj, float clearance, float* ox,
                 float* oy, float* oz, float* ex, float* ey, float* ez, float* weight);
};

#define DAISY_SAMPLE_KERNELS(ATTRIBUTE, NAME)                                                      \
    ATTRIBUTE void NAME##Block(uint32_t seed, int first, int count, int total,                     \
                               const PatchGeometry& t, float* x, float* y, float* z) {             \
        stratifiedBlockOf<kBlock>(seed, first, count, total, t, x, y, z);                          \
    }                                                                                              \
    ATTRIBUTE void NAME##SmallBlock(uint32_t seed, int count, const PatchGeometry& t, float* x,    \
                                    float* y, float* z) {                                          \
        stratifiedBlockOf<kSmallBlock>(seed, 0, count, count, t, x, y, z);                         \
    }                                                                                              \
    ATTRIBUTE void NAME##Trim(int count, const float* xi, const float* yi, const float* zi,        \
                              const float* xj, const float* yj, const float* zj, vec3 ni, vec3 nj, \
                              float clearance, float* __restrict ox, float* __restrict oy,         \
                              float* __restrict oz, float* __restrict ex, float* __restrict ey,    \
                              float* __restrict ez, float* __restrict weight) {                    \
        trimSegmentsOf(count, xi, yi, zi, xj, yj, zj, ni, nj, clearance, ox, oy, oz, ex, ey, ez,   \
                       weight);                                                                    \
    }                                                                                              \
    constexpr SampleKernels NAME##Kernels{NAME##Block, NAME##SmallBlock, NAME##Trim};

DAISY_SAMPLE_KERNELS(, baseline)
#ifdef DAISY_SAMPLES_AVX2
DAISY_SAMPLE_KERNELS(__attribute__((target("avx2"))), avx2)
#endif

const SampleKernels& sampleKernels() {
#ifdef DAISY_SAMPLES_AVX2
    static const SampleKernels& chosen = cpuIsa() >= CpuIsa::Avx2 ? avx2Kernels : baselineKernels;
    return chosen;
#else
    return baselineKernels;
#endif
}

// All `count` points of one stream, in index order.
void stratifiedPoints(uint32_t seed, int count, const PatchGeometry& t, float* x, float* y,
                      float* z) {
    const SampleKernels& kernels = sampleKernels();
    if (count <= kSmallBlock) {
        kernels.smallBlock(seed, count, t, x, y, z);
        return;
    }
    for (int first = 0; first < count; first += kBlock) {
        const int n = std::min(kBlock, count - first);
        kernels.block(seed, first, n, count, t, x + first, y + first, z + first);
    }
}

// Both streams draw point indices 0 .. count - 1; the second is paired through a permutation.
// Computing each stream's points in index order and pairing afterwards gives the same points as
// visibilitySamplePair's per-k calls. Writes pi, pj as structure-of-arrays (x, y, z each).
void samplesSoA(uint32_t pairSeedValue, int count, const PatchGeometry& i, const PatchGeometry& j,
                float* xi, float* yi, float* zi, float* xj, float* yj, float* zj, float* scratch) {
    const std::size_t n = std::size_t(count);
    float *x1 = scratch, *y1 = x1 + n, *z1 = y1 + n;
    const bool jFirst = shared::patchPrecedes(j, i);
    float* x0 = jFirst ? xj : xi;
    float* y0 = jFirst ? yj : yi;
    float* z0 = jFirst ? zj : zi;
    stratifiedPoints(shared::streamSeed(pairSeedValue, 0u), count, jFirst ? j : i, x0, y0, z0);
    stratifiedPoints(shared::streamSeed(pairSeedValue, 1u), count, jFirst ? i : j, x1, y1, z1);
    float* x2 = jFirst ? xi : xj;
    float* y2 = jFirst ? yi : yj;
    float* z2 = jFirst ? zi : zj;
    const uint32_t permutation = shared::streamSeed(pairSeedValue, 2u);
    for (int k = 0; k < count; ++k) {
        const uint32_t m = shared::permuteIndex(uint32_t(k), uint32_t(count), permutation);
        x2[k] = x1[m];
        y2[k] = y1[m];
        z2[k] = z1[m];
    }
}

// Scratch for up to kStack samples on the stack, more on the heap.
struct SampleBuffers {
    static constexpr int kStack = 256;
    float stack[9 * kStack];
    std::vector<float> heap;
    float* data;
    explicit SampleBuffers(int count) : data(stack) {
        if (count > kStack) {
            heap.resize(9 * std::size_t(count));
            data = heap.data();
        }
    }
};

}  // namespace

void visibilitySamples(uint32_t pairSeedValue, int count, const PatchGeometry& i,
                       const PatchGeometry& j, vec3* pi, vec3* pj) {
    SampleBuffers buffers(count);
    const std::size_t n = std::size_t(count);
    float* b = buffers.data;
    samplesSoA(pairSeedValue, count, i, j, b, b + n, b + 2 * n, b + 3 * n, b + 4 * n, b + 5 * n,
               b + 6 * n);
    for (std::size_t k = 0; k < n; ++k) {
        pi[k] = vec3(b[k], b[n + k], b[2 * n + k]);
        pj[k] = vec3(b[3 * n + k], b[4 * n + k], b[5 * n + k]);
    }
}

void shadowSegments(uint32_t pairSeedValue, int count, const PatchGeometry& i,
                    const PatchGeometry& j, float clearance, SegmentArrays& out, std::size_t offset,
                    float* weights) {
    SampleBuffers buffers(count);
    const std::size_t n = std::size_t(count);
    float* b = buffers.data;
    samplesSoA(pairSeedValue, count, i, j, b, b + n, b + 2 * n, b + 3 * n, b + 4 * n, b + 5 * n,
               b + 6 * n);
    sampleKernels().trim(count, b, b + n, b + 2 * n, b + 3 * n, b + 4 * n, b + 5 * n, i.normal,
                         j.normal, clearance, out.x0.data() + offset, out.y0.data() + offset,
                         out.z0.data() + offset, out.x1.data() + offset, out.y1.data() + offset,
                         out.z1.data() + offset, weights);
}

}  // namespace daisy
