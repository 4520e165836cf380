// The settings sweep's pieces that need no pipeline run (bench/sweep.h): the furnace oracle
// against its closed form, the Pareto front and cheapest row, the CSV's shape, and the files'
// names as the header documents them.
#include "bench/sweep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "geometry/patch_mesh.h"
#include "radiosity/radiosity_system.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

// One diagonal operator rho(k) on every patch, emission `emission(i, k)`, unit bins.
RadiositySystem uniformSystem(const PatchMesh& patches, const std::vector<double>& rho,
                              double (*emission)(std::size_t, std::size_t)) {
    RadiositySystem system;
    system.patchCount = uint32_t(patches.patchCount());
    system.wavelengthCount = rho.size();
    system.wavelengthsNm = {450, 550, 650};
    system.wavelengthsNm.resize(rho.size());
    system.binWidthsNm.assign(rho.size(), 1.0);
    system.areas = patches.areas;
    system.patchOperator.assign(patches.patchCount(), 0);
    for (std::size_t i = 0; i < patches.patchCount(); ++i)
        for (std::size_t k = 0; k < rho.size(); ++k)
            system.emission.push_back(emission(i, k));
    MaterialOperator op;
    op.matrix.size = rho.size();
    op.matrix.values.assign(rho.size() * rho.size(), 0.0);
    for (std::size_t k = 0; k < rho.size(); ++k)
        op.matrix(k, k) = rho[k];
    finishOperator(op, system.binWidthsNm);
    system.operators = {op};
    return system;
}

double unitEmission(std::size_t, std::size_t k) {
    return k == 0 ? 1.0 : 3.0;
}
double unevenEmission(std::size_t i, std::size_t) {
    return i == 0 ? 2.0 : 1.0;
}

TEST(FurnaceSolution, ClosedRoomIsEmissionOverOneMinusRho) {
    // A closed enclosure with one reflectance and uniform emission: F's rows sum to 1 and
    // every patch gathers B, so B = E + rho B and B = E / (1 - rho) (the white furnace).
    auto patches = buildPatchMesh(verify::unitCubeRoom(2), 0);
    ASSERT_TRUE(patches) << patches.error().message;
    const RadiositySystem system = uniformSystem(*patches, {0.5, 0.75}, unitEmission);
    const auto b = furnaceSolution(*patches, system);
    ASSERT_TRUE(b.has_value());
    ASSERT_EQ(b->size(), patches->patchCount() * 2);
    for (std::size_t i = 0; i < patches->patchCount(); ++i) {
        EXPECT_DOUBLE_EQ((*b)[i * 2], 1.0 / (1 - 0.5));
        EXPECT_DOUBLE_EQ((*b)[i * 2 + 1], 3.0 / (1 - 0.75));
    }
}

TEST(FurnaceSolution, AnythingButAFurnaceHasNoClosedForm) {
    auto room = buildPatchMesh(verify::unitCubeRoom(1), 0);
    ASSERT_TRUE(room) << room.error().message;
    // Uneven emission, rho = 1 (no finite answer), and an open mesh (two facing squares).
    EXPECT_FALSE(furnaceSolution(*room, uniformSystem(*room, {0.5}, unevenEmission)));
    EXPECT_FALSE(furnaceSolution(*room, uniformSystem(*room, {1.0}, unitEmission)));
    auto open = buildPatchMesh(verify::parallelSquares(1), 0);
    ASSERT_TRUE(open) << open.error().message;
    EXPECT_FALSE(furnaceSolution(*open, uniformSystem(*open, {0.5}, unitEmission)));
}

SweepRow row(const std::string& axis, double seconds, double meanDeltaE) {
    SweepRow r;
    r.axis = axis;
    r.label = axis;
    r.totalSeconds = seconds;
    r.meanDeltaE = meanDeltaE;
    return r;
}

TEST(SweepReport, ParetoFrontAndTheCheapestRowUnderTheJnd) {
    // (1 s, 3) and (2 s, 0.5) are undominated; (3 s, 0.8) is slower and worse than (2 s, 0.5);
    // the failed row is left out however good its numbers. The cheapest row under a mean
    // CIEDE2000 of 1 is the 2 s one.
    std::vector<SweepRow> rows = {row("default", 1, 3), row("rays", 3, 0.8), row("method", 2, 0.5),
                                  row("backend", 0.5, 0.1)};
    rows[3].error = "no device";
    EXPECT_EQ(markParetoFront(rows), 2);
    EXPECT_TRUE(rows[0].pareto);
    EXPECT_FALSE(rows[1].pareto);
    EXPECT_TRUE(rows[2].pareto);
    EXPECT_FALSE(rows[3].pareto);

    std::vector<SweepRow> slow = {row("default", 1, 3), row("rays", 2, 1.5)};
    EXPECT_EQ(markParetoFront(slow), -1);
}

TEST(SweepReport, CsvHasOneColumnPerHeaderFieldAndNoStrayCommas) {
    std::vector<SweepRow> rows = {row("default", 1, 0.5), row("backend", NAN, NAN)};
    rows[1].error = "vulkan: no device, none at all\nsecond line";
    std::istringstream csv(sweepCsv("scene", rows));
    std::string header, line;
    std::getline(csv, header);
    const auto fields = [](const std::string& text) {
        return std::count(text.begin(), text.end(), ',') + 1;
    };
    EXPECT_EQ(fields(header), 28);
    int lines = 0;
    while (std::getline(csv, line)) {
        ++lines;
        EXPECT_EQ(fields(line), fields(header)) << line;
        EXPECT_EQ(line.rfind("scene,", 0), 0u) << line;
    }
    EXPECT_EQ(lines, 2);  // the message's newline became a space
}

TEST(SweepFiles, NamesFollowTheCsv) {
    const SweepFiles byDefault = sweepFiles("assets/scenes/cornell_box.gltf", "", "");
    EXPECT_EQ(byDefault.csv, "bench-cornell_box.csv");
    EXPECT_EQ(byDefault.chart, "bench-cornell_box.png");
    EXPECT_EQ(byDefault.referenceImage, "bench-cornell_box-reference.png");
    EXPECT_EQ(byDefault.referenceCache, "bench-cornell_box.reference.bin");
    const SweepFiles given = sweepFiles("box.obj", "out/run.csv", "cache");
    EXPECT_EQ(given.csv, "out/run.csv");
    EXPECT_EQ(given.chart, "out/run.png");
    EXPECT_EQ(given.referenceImage, "out/run-reference.png");
    EXPECT_EQ(given.referenceCache, "cache/box.bench-reference.bin");
}

}  // namespace
}  // namespace daisy
