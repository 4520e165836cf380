// The bench against the path tracer, the parts that need no rendering (bench/path_bench.h): the
// time the path tracer needs for a target error, on curves that follow the Monte Carlo law
// error = c / sqrt(time) exactly, and the files' names as the header documents them.
#include "bench/path_bench.h"

#include <gtest/gtest.h>

#include <cmath>

namespace daisy {
namespace {

PathBenchRow pathRow(double seconds, double error) {
    PathBenchRow row;
    row.kind = "path";
    row.seconds = seconds;
    row.error.relativeRmsYDenoised = error;
    return row;
}

// error = 0.2 / sqrt(t): reaching 0.02 takes t = (0.2 / 0.02)^2 = 100 s exactly.
std::vector<PathBenchRow> curve(std::initializer_list<double> seconds) {
    std::vector<PathBenchRow> rows;
    for (double t : seconds)
        rows.push_back(pathRow(t, 0.2 / std::sqrt(t)));
    return rows;
}

TEST(PathTimeTo, InterpolatesAPowerLawExactlyInLogLog) {
    std::vector<PathBenchRow> rows = curve({1, 4, 16, 64, 256});
    PathBenchRow radiosity = pathRow(0.5, 0.001);  // not the path tracer's: ignored
    radiosity.kind = "radiosity";
    rows.insert(rows.begin() + 2, radiosity);
    bool extrapolated = true;
    EXPECT_NEAR(pathTimeTo(rows, 0.02, extrapolated), 100, 1e-9);
    EXPECT_FALSE(extrapolated);
    // Already under the target at the first row: that row's time.
    EXPECT_EQ(pathTimeTo(rows, 0.5, extrapolated), 1);
    EXPECT_FALSE(extrapolated);
}

TEST(PathTimeTo, ExtrapolatesPastTheCurveByOneOverSqrtTime) {
    bool extrapolated = false;
    EXPECT_NEAR(pathTimeTo(curve({1, 4, 16}), 0.02, extrapolated), 100, 1e-9);
    EXPECT_TRUE(extrapolated);
    EXPECT_TRUE(std::isnan(pathTimeTo({}, 0.02, extrapolated)));
}

TEST(PathBenchFiles, NamesFollowTheCsv) {
    const PathBenchFiles byDefault = pathBenchFiles("assets/scenes/cornell_box.gltf", "", "");
    EXPECT_EQ(byDefault.csv, "bench-path-cornell_box.csv");
    EXPECT_EQ(byDefault.chart, "bench-path-cornell_box.png");
    EXPECT_EQ(byDefault.referenceImage, "bench-path-cornell_box.reference.png");
    EXPECT_EQ(byDefault.referenceCache, "bench-path-cornell_box.path-reference.bin");
    EXPECT_EQ(byDefault.errorImage("default"), "bench-path-cornell_box.error-default.png");
    const PathBenchFiles given = pathBenchFiles("box.obj", "out/cb.csv", "cache");
    EXPECT_EQ(given.chart, "out/cb.png");
    EXPECT_EQ(given.errorImage("gather-none"), "out/cb.error-gather-none.png");
    EXPECT_EQ(given.referenceCache, "cache/box.path-reference.bin");
}

}  // namespace
}  // namespace daisy
