// Runs `daisy bench SCENE` (bench/sweep.h) on the white furnace, whose
// reference is analytic (B = E / (1 - rho) = 2 everywhere): the CSV's rows carry their real
// errors against it, the plot and the reference image are written, and a second run reads the
// cached reference instead of recomputing it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "image/image_io.h"
#include "test_util.h"

namespace daisy {
namespace {

using test::runDaisy;
using test::RunResult;

const std::string kFurnace = test::assetPath("scenes/furnace_box.gltf");

std::vector<std::string> splitCsv(const std::string& line) {
    std::vector<std::string> fields;
    std::stringstream in(line);
    std::string field;
    while (std::getline(in, field, ','))
        fields.push_back(field);
    return fields;
}

// Rows of the CSV keyed by "axis/setting", each a map column -> text.
std::map<std::string, std::map<std::string, std::string>> readRows(const std::string& path) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    const std::vector<std::string> header = splitCsv(line);
    std::map<std::string, std::map<std::string, std::string>> rows;
    while (std::getline(in, line)) {
        const std::vector<std::string> fields = splitCsv(line);
        std::map<std::string, std::string> row;
        for (std::size_t k = 0; k < header.size() && k < fields.size(); ++k)
            row[header[k]] = fields[k];
        rows[row["axis"] + "/" + row["setting"]] = row;
    }
    return rows;
}

TEST(BenchCli, FurnaceSweepMeasuresAgainstTheAnalyticAnswer) {
    const auto dir = test::testTempDir();
    const std::string csv = (dir / "furnace.csv").string();
    RunResult run = runDaisy("bench " + kFurnace + " --reference daisy --quick -o " + csv);
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("reference is the analytic furnace solution"), std::string::npos)
        << run.output;

    const auto rows = readRows(csv);
    ASSERT_TRUE(rows.count("default/default")) << run.output;
    const auto& standard = rows.at("default/default");
    // Hybrid L = 1 on the closed cube: row sums within 1e-3 of 1, so B within ~1e-3 of 2.
    EXPECT_LT(std::stod(standard.at("rel_rms_B")), 1e-3);
    EXPECT_LT(std::stod(standard.at("mean_dE00")), 0.1);
    EXPECT_EQ(standard.at("converged"), "1");
    EXPECT_GT(std::stod(standard.at("total_s")), 0);
    EXPECT_GT(std::stoull(standard.at("peak_bytes")), 0u);
    // Stopping the solve at a relative residual of 1e-2 leaves an error of that order.
    ASSERT_TRUE(rows.count("tolerance/tol=0.01"));
    const double loose = std::stod(rows.at("tolerance/tol=0.01").at("rel_rms_B"));
    EXPECT_GT(loose, 1e-3);
    EXPECT_LT(loose, 5e-2);
    // The daisyriot set's 350 nm sample lies outside the reference's range and is left out:
    // flat spectra compare exactly.
    ASSERT_TRUE(rows.count("wavelengths/daisyriot"));
    EXPECT_LT(std::stod(rows.at("wavelengths/daisyriot").at("rel_rms_B")), 1e-3);
    int front = 0;
    for (const auto& [key, row] : rows)
        front += row.at("pareto") == "1";
    EXPECT_GE(front, 1);

    auto plot = readPng((dir / "furnace.png").string());
    ASSERT_TRUE(plot.ok()) << plot.error().message;
    EXPECT_EQ(plot->width, 1100);
    auto reference = readPng((dir / "furnace-reference.png").string());
    ASSERT_TRUE(reference.ok()) << reference.error().message;
    EXPECT_EQ(reference->width, 96);

    run = runDaisy("bench " + kFurnace + " --reference daisy --quick -o " + csv);
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("reference read from"), std::string::npos) << run.output;
}

TEST(BenchCli, SweepWithoutSceneIsStatusTwo) {
    const RunResult run = runDaisy("bench");
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("give a SCENE"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace daisy
