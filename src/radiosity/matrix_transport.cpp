#include "radiosity/matrix_transport.h"

#include <algorithm>

#include "core/check.h"
#include "core/strings.h"
#include "radiosity/matrix_market.h"

namespace daisy {

MatrixTransport::MatrixTransport(SparseMatrix matrix)
    : matrix_(std::move(matrix)), rowSums_(daisy::rowSums(matrix_)) {}

TransportStats MatrixTransport::stats() const {
    return {matrix_.nonzeroCount(), matrix_.bytes()};
}

void MatrixTransport::gather(std::span<const double> radiosity, std::size_t wavelengthCount,
                             std::span<double> gathered, int threads) const {
    gatherAll(matrix_, radiosity, wavelengthCount, gathered, threads);
}

void MatrixTransport::gatherFrom(std::span<const uint8_t> sources,
                                 std::span<const uint8_t> receivers,
                                 std::span<const double> radiosity, std::size_t wavelengthCount,
                                 std::span<double> gathered) const {
    const std::size_t n = matrix_.size, m = wavelengthCount;
    DAISY_CHECK(sources.size() == n && receivers.size() == n && radiosity.size() == n * m &&
                gathered.size() == n * m);
    for (uint32_t i = 0; i < n; ++i) {
        if (!receivers[i]) continue;
        double* g = gathered.data() + std::size_t(i) * m;
        std::fill(g, g + m, 0.0);
        const auto columns = matrix_.rowColumns(i);
        const auto values = matrix_.rowValues(i);
        for (std::size_t e = 0; e < columns.size(); ++e) {
            if (!sources[columns[e]]) continue;
            const double* bj = radiosity.data() + std::size_t(columns[e]) * m;
            for (std::size_t k = 0; k < m; ++k)
                g[k] += double(values[e]) * bj[k];
        }
    }
}

void rowEntries(const SparseMatrix& matrix, uint32_t row, std::vector<TransportEntry>& out) {
    const auto columns = matrix.rowColumns(row);
    const auto values = matrix.rowValues(row);
    out.resize(columns.size());
    for (std::size_t e = 0; e < columns.size(); ++e)
        out[e] = {columns[e], values[e]};
}

void MatrixTransport::row(uint32_t patch, std::vector<TransportEntry>& out) const {
    rowEntries(matrix_, patch, out);
}

const SparseMatrix& MatrixTransport::transposed() const {
    std::call_once(transposeOnce_, [&] { transposed_ = transpose(matrix_); });
    return *transposed_;
}

Expected<SolverResult> MatrixTransport::solve(const RadiositySystem& system,
                                              SolverSettings settings) const {
    if (settings.rowSums.empty()) settings.rowSums = rowSums_;
    if (settings.kind == SolverKind::Southwell && !settings.transposed)
        settings.transposed = &transposed();
    return solveRadiosity(matrix_, system, settings);
}

Expected<void> MatrixTransport::writeMatrixMarket(const std::string& path,
                                                  const std::vector<std::string>& comments) const {
    return daisy::writeMatrixMarket(path, matrix_, comments);
}

Expected<MatrixComparison> MatrixTransport::compare(const Transport& other,
                                                    const MatrixCompareSettings& settings) const {
    const auto* matrix = dynamic_cast<const MatrixTransport*>(&other);
    if (!matrix) {
        return Error{concat("cannot compare the matrix transport with the ", other.kind(),
                            " transport entry by entry")};
    }
    if (matrix->matrix_.size != matrix_.size) {
        return Error{concat("cannot compare transports of ", matrix_.size, " and ",
                            matrix->matrix_.size, " patches")};
    }
    return compareMatrices(matrix_, matrix->matrix_, settings);
}

std::shared_ptr<const Transport> denseTransport(
    uint32_t n, const std::function<float(uint32_t i, uint32_t j)>& factor) {
    SparseMatrix f = SparseMatrix::zeros(n);
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < n; ++j) {
            const float value = factor(i, j);
            if (value != 0) f.columns.push_back(j), f.values.push_back(value);
        }
        f.rowOffsets[i + 1] = f.columns.size();
    }
    return std::make_shared<MatrixTransport>(std::move(f));
}

}  // namespace daisy
