#pragma once
// Memory estimate of the sparse view-factor matrix before it is built (DESIGN.md section 3:
// print it first, refuse over --max-memory). Only pairs whose patches face each other can have
// a non-zero F_ij, so the non-zero count is estimated from the facing fraction of the pairs
// (all pairs for small meshes, a fixed-seed sample of pairs for large ones).
#include <cstdint>

#include "geometry/patch_mesh.h"

namespace daisy {

struct MatrixEstimate {
    uint64_t patchCount = 0;
    double facingFraction = 0;  // of ordered pairs i != j, in [0, 1]
    bool sampled = false;  // true when facingFraction comes from a sample of pairs
    uint64_t nonzeros = 0;  // estimated stored entries
    uint64_t matrixBytes = 0;  // CSR: 8 (n + 1) + (4 + 4) x nonzeros
};

MatrixEstimate estimateMatrixMemory(const PatchMesh& mesh);

}  // namespace daisy
