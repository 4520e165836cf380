#include "spectral/cie_tables.h"

#include <gtest/gtest.h>

namespace daisy {
namespace {

// Spot values from the CIE 015:2018 tables (as printed in assets/reference/*.csv).
TEST(CieTables, ColourMatchingFunctions) {
    EXPECT_EQ(kCie1931Cmf.size(), 471u);
    const auto& at555 = kCie1931Cmf[555 - kCieCmfFirstNm];
    EXPECT_DOUBLE_EQ(at555[1], 1.0);  // ybar peaks at 1 at 555 nm by definition
    EXPECT_DOUBLE_EQ(kCie1931Cmf[600 - kCieCmfFirstNm][0], 1.0622);
    EXPECT_DOUBLE_EQ(kCie1931Cmf[450 - kCieCmfFirstNm][2], 1.77211);
    EXPECT_DOUBLE_EQ(kCie1931Cmf.front()[0], 0.0001299);
}

TEST(CieTables, Illuminants) {
    const char* names[] = {"A",  "D50", "D65", "F1", "F2",  "F3",  "F4", "F5",
                           "F6", "F7",  "F8",  "F9", "F10", "F11", "F12"};
    for (const char* name : names) {
        const CieIlluminantTable* table = findCieIlluminant(name);
        ASSERT_NE(table, nullptr) << name;
        EXPECT_DOUBLE_EQ(table->stepNm, 5);
    }
    EXPECT_EQ(findCieIlluminant("F13"), nullptr);
    const CieIlluminantTable& d65 = *findCieIlluminant("D65");
    EXPECT_DOUBLE_EQ(d65.firstNm, 300);
    EXPECT_EQ(d65.values.size(), 107u);
    // A, D50 and D65 are normalised to 100 at 560 nm (CIE 015:2018 section 4).
    for (const char* name : {"A", "D50", "D65"})
        EXPECT_DOUBLE_EQ(evaluateCieIlluminant(*findCieIlluminant(name), 560), 100) << name;
    EXPECT_DOUBLE_EQ(evaluateCieIlluminant(d65, 562.5),
                     (d65.values[52] + d65.values[53]) / 2);  // linear between 560 and 565
    EXPECT_EQ(evaluateCieIlluminant(d65, 299), 0);
    EXPECT_EQ(evaluateCieIlluminant(*findCieIlluminant("F1"), 790), 0);  // F ends at 780 nm
}

}  // namespace
}  // namespace daisy
