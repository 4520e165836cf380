// CSR storage, its Matrix Market export and the patch table (DESIGN.md sections 3 and 9). The
// oracle is a small matrix written out by hand.
#include "radiosity/sparse_matrix.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "radiosity/matrix_market.h"
#include "radiosity/patch_csv.h"
#include "test_util.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

// [[0, 0.5, 0], [0.25, 0, 0.125], [0, 0, 0]]
SparseMatrix smallMatrix() {
    SparseMatrix m = SparseMatrix::zeros(3);
    m.rowOffsets = {0, 1, 3, 3};
    m.columns = {1, 0, 2};
    m.values = {0.5f, 0.25f, 0.125f};
    return m;
}

std::string readText(const std::string& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

TEST(SparseMatrix, LookupSumsAndStructure) {
    const SparseMatrix m = smallMatrix();
    EXPECT_EQ(validateStructure(m), "");
    EXPECT_EQ(m.at(0, 1), 0.5f);
    EXPECT_EQ(m.at(1, 2), 0.125f);
    EXPECT_EQ(m.at(2, 2), 0.0f);
    EXPECT_EQ(rowSums(m), (std::vector<double>{0.5, 0.375, 0.0}));
    EXPECT_EQ(m.bytes(), 8u * 4 + 8u * 3);
}

TEST(SparseMatrix, TransposeAndDropZeros) {
    const SparseMatrix t = transpose(smallMatrix());
    EXPECT_EQ(t.rowOffsets, (std::vector<uint64_t>{0, 1, 2, 3}));
    EXPECT_EQ(t.columns, (UninitializedVector<uint32_t>{1, 0, 1}));
    EXPECT_EQ(t.at(2, 1), 0.125f);

    SparseMatrix m = smallMatrix();
    m.values[1] = 0.0f;
    dropZeros(m);
    EXPECT_EQ(validateStructure(m), "");
    EXPECT_EQ(m.rowOffsets, (std::vector<uint64_t>{0, 1, 2, 2}));
    EXPECT_EQ(m.columns, (UninitializedVector<uint32_t>{1, 2}));
}

// Three patches of areas 1, 2, 4 with symmetric A_i F_ij = 0.8 (0-1), 0.6 (0-2), 1.0 (1-2):
// row 0 sums to 1.4, the others to 0.9 and 0.4. Capping scales row 0 and column 0 by 1 / 1.4 and
// leaves F_12, F_21 alone; reciprocity holds after it.
TEST(SparseMatrix, CapRowSumsConservesAndKeepsReciprocity) {
    const double area[3] = {1, 2, 4};
    SparseMatrix m = SparseMatrix::zeros(3);
    m.rowOffsets = {0, 2, 4, 6};
    m.columns = {1, 2, 0, 2, 0, 1};
    m.values = {0.8f, 0.6f, 0.4f, 0.5f, 0.15f, 0.25f};
    const RowSumCap cap = capRowSums(m);
    EXPECT_EQ(cap.rowsCapped, 1u);
    EXPECT_NEAR(cap.largestRowSum, 1.4, 1e-6);
    const std::vector<double> sums = rowSums(m);
    EXPECT_NEAR(sums[0], 1.0, 1e-6);
    EXPECT_NEAR(sums[1], 0.4 / 1.4 + 0.5, 1e-6);
    EXPECT_NEAR(sums[2], 0.15 / 1.4 + 0.25, 1e-6);
    EXPECT_EQ(m.at(1, 2), 0.5f);
    EXPECT_EQ(m.at(2, 1), 0.25f);
    for (uint32_t i = 0; i < 3; ++i) {
        for (uint32_t j = 0; j < 3; ++j)
            EXPECT_NEAR(area[i] * m.at(i, j), area[j] * m.at(j, i), 1e-6) << i << ", " << j;
    }
    // Nothing over 1 is left: a second pass finds at most rounding.
    EXPECT_LE(capRowSums(m).largestRowSum, 1.0 + 1e-6);
    // A matrix within the rule is not touched.
    SparseMatrix small = smallMatrix();
    EXPECT_EQ(capRowSums(small).rowsCapped, 0u);
    EXPECT_EQ(small.values, smallMatrix().values);
}

TEST(SparseMatrix, StructureErrorsAreNamed) {
    SparseMatrix m = smallMatrix();
    m.columns[2] = 0;  // row 1: 0, 0
    EXPECT_NE(validateStructure(m).find("row 1"), std::string::npos);
}

TEST(MatrixMarket, WritesOneBasedCoordinatesAndReadsThemBack) {
    const auto dir = test::testTempDir();
    const std::string path = (dir / "F.mtx").string();
    ASSERT_TRUE(writeMatrixMarket(path, smallMatrix(), {"a comment"}).ok());
    EXPECT_EQ(readText(path),
              "%%MatrixMarket matrix coordinate real general\n% a comment\n3 3 3\n"
              "1 2 0.5\n2 1 0.25\n2 3 0.125\n");
    auto back = readMatrixMarket(path);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->rowOffsets, smallMatrix().rowOffsets);
    EXPECT_EQ(back->columns, smallMatrix().columns);
    EXPECT_EQ(back->values, smallMatrix().values);
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp-" + std::to_string(getpid())));
}

// Shortest round-trip text: every float reads back bit for bit.
TEST(MatrixMarket, ValuesRoundTripExactly) {
    SparseMatrix m = SparseMatrix::zeros(2);
    m.rowOffsets = {0, 2, 2};
    m.columns = {0, 1};
    m.values = {0.1f, 1.0f / 3.0f};
    const std::string path = (test::testTempDir() / "F.mtx").string();
    ASSERT_TRUE(writeMatrixMarket(path, m).ok());
    EXPECT_EQ(readMatrixMarket(path)->values, m.values);
}

TEST(MatrixMarket, ReadErrorsNameTheLine) {
    const auto dir = test::testTempDir();
    const std::string bad = test::writeFile(
        dir, "bad.mtx", "%%MatrixMarket matrix coordinate real general\n2 2 1\n3 1 0.5\n");
    auto result = readMatrixMarket(bad);
    ASSERT_FALSE(result.ok());
    EXPECT_NE(result.error().message.find("bad.mtx:3: index out of range"), std::string::npos)
        << result.error().message;
}

TEST(MatrixMarket, UnwritablePathIsAnErrorNamingIt) {
    auto result = writeMatrixMarket("/nonexistent_dir/F.mtx", smallMatrix());
    ASSERT_FALSE(result.ok());
    EXPECT_NE(result.error().message.find("/nonexistent_dir/F.mtx"), std::string::npos);
}

TEST(PatchCsv, HeaderRowsAndAppendedColumns) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, 1);
    const PatchMesh patches = verify::patchesOf(mesh);
    const std::string names[] = {"paint, \"red\""};
    const double energy[] = {1, 2, 3, 4};  // 2 patches x 2 columns
    const PatchCsvColumns extra[] = {{{"E_400", "E_500"}, energy}};
    const std::string path = (test::testTempDir() / "patches.csv").string();
    ASSERT_TRUE(writePatchCsv(path, patches, names, extra).ok());
    EXPECT_EQ(readText(path),
              "patch,triangle,area,cx,cy,cz,nx,ny,nz,material,E_400,E_500\n"
              "0,0,0.5,0.6666666666666666,0.3333333333333333,0,0,0,1,\"paint, \"\"red\"\"\",1,2\n"
              "1,1,0.5,0.3333333333333333,0.6666666666666666,0,0,0,1,\"paint, \"\"red\"\"\",3,4\n");
}

TEST(PatchCsv, MismatchedColumnsAreRefusedWithoutAFile) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, 1);
    const double one[] = {1};
    const PatchCsvColumns extra[] = {{{"X"}, one}};
    const std::string path = (test::testTempDir() / "patches.csv").string();
    EXPECT_FALSE(writePatchCsv(path, verify::patchesOf(mesh), {}, extra).ok());
    EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace daisy
