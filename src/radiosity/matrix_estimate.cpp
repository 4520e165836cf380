#include "radiosity/matrix_estimate.h"

#include <cmath>
#include <random>

namespace daisy {
namespace {

constexpr uint64_t kExactPatchLimit = 2000;  // up to here all n (n - 1) ordered pairs are tested
constexpr uint64_t kSampledPairs = 200000;  // standard error of the fraction <= 0.0012
constexpr uint64_t kSampleSeed = 0x9e3779b97f4a7c15ULL;

// Each patch's centroid lies strictly in front of the other's plane. For flat patches, some point
// of each in front of the other is necessary for F_ij != 0; testing centroids only is a heuristic
// (a pair facing at its edges but not at its centroids is missed, occluded pairs are counted).
// The test is symmetric in i and j.
bool facing(const PatchMesh& mesh, std::size_t i, std::size_t j) {
    const Vec3d d = mesh.centroids[j] - mesh.centroids[i];
    return dot(mesh.normals[i], d) > 0 && dot(mesh.normals[j], -d) > 0;
}

uint64_t saturatingAdd(uint64_t a, uint64_t b) {
    return a > UINT64_MAX - b ? UINT64_MAX : a + b;
}

uint64_t saturatingMultiply(uint64_t a, uint64_t b) {
    return b != 0 && a > UINT64_MAX / b ? UINT64_MAX : a * b;
}

}  // namespace

MatrixEstimate estimateMatrixMemory(const PatchMesh& mesh) {
    MatrixEstimate estimate;
    const uint64_t n = mesh.patchCount();
    estimate.patchCount = n;
    if (n >= 2 && n <= kExactPatchLimit) {
        uint64_t facingPairs = 0;  // unordered
        for (std::size_t i = 0; i < n; ++i) {
            for (std::size_t j = i + 1; j < n; ++j)
                facingPairs += facing(mesh, i, j) ? 1 : 0;
        }
        estimate.facingFraction = static_cast<double>(2 * facingPairs) / (double(n) * (n - 1));
    } else if (n > kExactPatchLimit) {
        // Uniform over ordered pairs i != j; modulo bias is below n / 2^64.
        std::mt19937_64 rng(kSampleSeed);
        uint64_t facingPairs = 0;
        for (uint64_t s = 0; s < kSampledPairs; ++s) {
            const uint64_t i = rng() % n;
            uint64_t j = rng() % (n - 1);
            if (j >= i) ++j;
            facingPairs += facing(mesh, i, j) ? 1 : 0;
        }
        estimate.facingFraction = static_cast<double>(facingPairs) / kSampledPairs;
        estimate.sampled = true;
    }
    const double nonzeros =
        n < 2 ? 0.0 : std::round(estimate.facingFraction * double(n) * double(n - 1));
    estimate.nonzeros = nonzeros < 0x1p64 ? static_cast<uint64_t>(nonzeros) : UINT64_MAX;
    // CSR: uint64 row offsets, then a uint32 column and a float value per stored entry.
    estimate.matrixBytes = saturatingAdd(saturatingMultiply(8, saturatingAdd(n, 1)),
                                         saturatingMultiply(8, estimate.nonzeros));
    return estimate;
}

}  // namespace daisy
