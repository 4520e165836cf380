#pragma once
// The all-pairs transport: T = F, the view-factor matrix in CSR (radiosity/sparse_matrix.h),
// built by a backend (backend/backend.h) or read from the disk cache. It keeps what every solve
// derives from F: the row sums (computed with F) and the transpose (Southwell's column access,
// computed on first use).
#include <functional>
#include <memory>
#include <mutex>
#include <optional>

#include "radiosity/sparse_matrix.h"
#include "radiosity/transport.h"

namespace daisy {

class MatrixTransport final : public Transport {
public:
    explicit MatrixTransport(SparseMatrix matrix);

    const char* kind() const override { return "matrix"; }
    uint32_t patchCount() const override { return matrix_.size; }
    TransportStats stats() const override;
    std::span<const double> rowSums() const override { return rowSums_; }
    std::string checkStructure() const override { return validateStructure(matrix_); }
    void gather(std::span<const double> radiosity, std::size_t wavelengthCount,
                std::span<double> gathered, int threads = 0) const override;
    void gatherFrom(std::span<const uint8_t> sources, std::span<const uint8_t> receivers,
                    std::span<const double> radiosity, std::size_t wavelengthCount,
                    std::span<double> gathered) const override;
    void row(uint32_t patch, std::vector<TransportEntry>& out) const override;
    Expected<SolverResult> solve(const RadiositySystem& system,
                                 SolverSettings settings) const override;
    Expected<void> writeMatrixMarket(const std::string& path,
                                     const std::vector<std::string>& comments) const override;
    Expected<MatrixComparison> compare(const Transport& other,
                                       const MatrixCompareSettings& settings) const override;

    // F itself, for the session's disk cache and the tests of the matrix path.
    const SparseMatrix& matrix() const { return matrix_; }

private:
    const SparseMatrix& transposed() const;

    SparseMatrix matrix_;
    std::vector<double> rowSums_;
    mutable std::once_flag transposeOnce_;
    mutable std::optional<SparseMatrix> transposed_;
};

// Row `row` of `matrix` as transport entries (`out` is replaced), columns ascending: the
// row() of every transport that stores factors in CSR.
void rowEntries(const SparseMatrix& matrix, uint32_t row, std::vector<TransportEntry>& out);

// A matrix transport of n patches with F_ij = factor(i, j), entries equal to 0 not stored:
// closed-form systems (the stress suite's exact furnace, tests). O(n^2) calls.
std::shared_ptr<const Transport> denseTransport(
    uint32_t n, const std::function<float(uint32_t i, uint32_t j)>& factor);

}  // namespace daisy
