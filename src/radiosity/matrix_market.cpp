#include "radiosity/matrix_market.h"

#include <tbb/parallel_pipeline.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/atomic_file.h"
#include "core/strings.h"

namespace daisy {
namespace {

constexpr uint64_t kEntriesPerChunk = 1 << 18;  // ~5 MB of text per formatted chunk

struct Chunk {
    uint32_t firstRow = 0;
    uint32_t endRow = 0;
    std::string text;
};

void appendRows(const SparseMatrix& matrix, Chunk& chunk) {
    char buffer[32];
    const auto put = [&](auto value, char separator) {
        const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
        chunk.text.append(buffer, result.ptr);
        chunk.text += separator;
    };
    for (uint32_t i = chunk.firstRow; i < chunk.endRow; ++i) {
        const auto cols = matrix.rowColumns(i);
        const auto vals = matrix.rowValues(i);
        for (std::size_t k = 0; k < cols.size(); ++k) {
            put(uint64_t(i) + 1, ' ');
            put(uint64_t(cols[k]) + 1, ' ');
            put(vals[k], '\n');
        }
    }
}

}  // namespace

Expected<void> writeMatrixMarket(const std::string& path, const SparseMatrix& matrix,
                                 const std::vector<std::string>& comments) {
    return writeFileAtomically(path, [&](std::FILE* file) -> std::string {
        std::fputs("%%MatrixMarket matrix coordinate real general\n", file);
        for (const std::string& comment : comments)
            std::fprintf(file, "%% %s\n", comment.c_str());
        std::fprintf(file, "%u %u %llu\n", matrix.size, matrix.size,
                     static_cast<unsigned long long>(matrix.nonzeroCount()));
        uint32_t nextRow = 0;
        bool failed = false;
        const std::size_t tokens = 2 * std::max(1u, std::thread::hardware_concurrency());
        tbb::parallel_pipeline(
            tokens,
            tbb::make_filter<void, Chunk>(
                tbb::filter_mode::serial_in_order,
                [&](tbb::flow_control& control) {
                    if (nextRow >= matrix.size) {
                        control.stop();
                        return Chunk{};
                    }
                    Chunk chunk;
                    chunk.firstRow = nextRow;
                    const uint64_t start = matrix.rowOffsets[nextRow];
                    while (nextRow < matrix.size &&
                           (nextRow == chunk.firstRow ||
                            matrix.rowOffsets[nextRow + 1] - start <= kEntriesPerChunk)) {
                        ++nextRow;
                    }
                    chunk.endRow = nextRow;
                    return chunk;
                }) &
                tbb::make_filter<Chunk, Chunk>(tbb::filter_mode::parallel,
                                               [&](Chunk chunk) {
                                                   appendRows(matrix, chunk);
                                                   return chunk;
                                               }) &
                tbb::make_filter<Chunk, void>(
                    tbb::filter_mode::serial_in_order, [&](const Chunk& chunk) {
                        if (failed) return;
                        failed = std::fwrite(chunk.text.data(), 1, chunk.text.size(), file) !=
                            chunk.text.size();
                    }));
        return failed ? "write failed" : "";
    });
}

Expected<SparseMatrix> readMatrixMarket(const std::string& path) {
    std::ifstream in(path);
    if (!in) return Error{path + ": cannot open"};
    std::string line;
    uint64_t lineNumber = 0;
    const auto fail = [&](const std::string& what) {
        return Error{concat(path, ":", lineNumber, ": ", what)};
    };
    if (!std::getline(in, line)) return Error{path + ": empty file"};
    ++lineNumber;
    if (toLower(line).rfind("%%matrixmarket matrix coordinate real general", 0) != 0) {
        return fail("expected '%%MatrixMarket matrix coordinate real general'");
    }
    uint64_t rows = 0, cols = 0, entries = 0;
    while (std::getline(in, line)) {
        ++lineNumber;
        if (line.empty() || line[0] == '%') continue;
        std::istringstream sizes(line);
        if (!(sizes >> rows >> cols >> entries)) return fail("expected 'rows columns entries'");
        break;
    }
    if (rows != cols || rows > UINT32_MAX) return fail("the matrix must be square, <= 2^32 rows");
    struct Entry {
        uint32_t row, col;
        float value;
    };
    std::vector<Entry> triplets;
    triplets.reserve(entries);
    while (triplets.size() < entries && std::getline(in, line)) {
        ++lineNumber;
        if (line.empty() || line[0] == '%') continue;
        std::istringstream fields(line);
        uint64_t i = 0, j = 0;
        double value = 0;
        if (!(fields >> i >> j >> value)) return fail("expected 'i j value'");
        if (i < 1 || i > rows || j < 1 || j > cols) return fail("index out of range");
        if (!std::isfinite(value)) return fail("non-finite value");
        triplets.push_back({uint32_t(i - 1), uint32_t(j - 1), static_cast<float>(value)});
    }
    if (triplets.size() != entries) return fail(concat("expected ", entries, " entries"));
    std::sort(triplets.begin(), triplets.end(), [](const Entry& a, const Entry& b) {
        return a.row != b.row ? a.row < b.row : a.col < b.col;
    });
    SparseMatrix matrix = SparseMatrix::zeros(static_cast<uint32_t>(rows));
    matrix.columns.reserve(entries);
    matrix.values.reserve(entries);
    for (std::size_t k = 0; k < triplets.size(); ++k) {
        if (k > 0 && triplets[k].row == triplets[k - 1].row &&
            triplets[k].col == triplets[k - 1].col) {
            return Error{concat(path, ": duplicate entry (", triplets[k].row + 1, ", ",
                                triplets[k].col + 1, ")")};
        }
        matrix.columns.push_back(triplets[k].col);
        matrix.values.push_back(triplets[k].value);
        ++matrix.rowOffsets[triplets[k].row + 1];
    }
    for (uint32_t i = 0; i < matrix.size; ++i)
        matrix.rowOffsets[i + 1] += matrix.rowOffsets[i];
    return matrix;
}

}  // namespace daisy
