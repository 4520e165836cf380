#pragma once
// Matrix Market export of F (DESIGN.md section 9): `coordinate real general`, 1-based, one line
// "i j F_ij" per stored entry in row-major order. Values are the stored floats written as the
// shortest decimal that reads back as the same float (at most 9 significant digits, the
// round-trip precision of binary32, i.e. no less exact than %.9g). Format: NIST, "The Matrix
// Market Exchange Formats: Initial Design" (Boisvert, Pozo, Remington 1996).
#include <string>
#include <vector>

#include "core/expected.h"
#include "radiosity/sparse_matrix.h"

namespace daisy {

// Writes `matrix` to `path` through a temporary file and a rename (no partial file on failure).
// `comments` become "% ..." lines after the banner. Formats rows in parallel, writes in order.
Expected<void> writeMatrixMarket(const std::string& path, const SparseMatrix& matrix,
                                 const std::vector<std::string>& comments = {});

// Reads a square `coordinate real general` file into CSR (entries may come in any order;
// duplicates are refused). Errors name the file and the line.
Expected<SparseMatrix> readMatrixMarket(const std::string& path);

}  // namespace daisy
