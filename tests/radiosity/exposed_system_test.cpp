// The exposed parts' system (radiosity/exposed_system.h): which patches get a scaled operator,
// by how much, and the conversions between exposed and whole-patch radiosity. The oracle is the
// formula s_i = 1 / max(phi_i, rowsum_i), rounded to 1/64, worked by hand. (The furnace with a
// box on its floor checks the solve end to end: tests/render/near_field_test.cpp.)
#include "radiosity/exposed_system.h"

#include <gtest/gtest.h>

#include <vector>

#include "solver_test_util.h"

namespace daisy {
namespace {

using solvertest::diagonalOperator;
using solvertest::makeSystem;

TEST(ExposedSystem, ScalesOnlyPartlyExposedPatchesByTheirExposedShare) {
    // Patches: exposed, half exposed (row 0.4), a quarter exposed with row 0.6 (the probe's
    // share under the row's: 0.6 rounds up to 39/64), buried (reflects nothing), half exposed
    // but black.
    RadiositySystem system = makeSystem(5, 1, {diagonalOperator({0.5}), diagonalOperator({0})});
    system.areas = {1, 2, 1, 1, 1};
    system.patchOperator = {0, 0, 0, 0, 1};
    const std::vector<float> phi = {1.0f, 0.5f, 0.25f, 0.0f, 0.5f};
    const std::vector<double> rows = {1.0, 0.4, 0.6, 0.0, 0.5};
    const ExposedSystem exposed = exposedSystem(system, phi, rows);
    ASSERT_TRUE(exposed.changed);
    EXPECT_EQ(exposed.phi, (std::vector<double>{1, 0.5, 0.25, 1, 1}));
    const RadiositySystem& s = exposed.system;
    EXPECT_EQ(s.operators.size(), 5u);  // the two originals, scales 2, 64 / 39 and 0
    EXPECT_EQ(s.patchOperator[0], 0u);
    EXPECT_TRUE(s.operators[s.patchOperator[3]].isZero);
    EXPECT_DOUBLE_EQ(s.areas[3], 1.0);
    EXPECT_EQ(s.patchOperator[4], 1u);
    EXPECT_DOUBLE_EQ(s.operators[s.patchOperator[1]].diagonal[0], 1.0);
    EXPECT_DOUBLE_EQ(s.operators[s.patchOperator[2]].diagonal[0], 0.5 * 64 / 39);
    EXPECT_DOUBLE_EQ(s.areas[1], 1.0);  // 2 / 2
    EXPECT_DOUBLE_EQ(s.areas[2], 39.0 / 64);
    EXPECT_DOUBLE_EQ(exposed.rowSums[1], 0.8);
    EXPECT_DOUBLE_EQ(exposed.rowSums[2], 0.6 * 64 / 39);
    EXPECT_EQ(exposed.rowSums[0], 1.0);

    // B = E + phi (B' - E) and back.
    system.emission = {0, 1, 0, 0, 0};
    std::vector<double> b = {2, 3, 4, 5, 6};
    exposedToWholePatch(system, exposed.phi, b);
    EXPECT_EQ(b, (std::vector<double>{2, 2, 1, 5, 6}));
    wholePatchToExposed(system, exposed.phi, b);
    EXPECT_EQ(b, (std::vector<double>{2, 3, 4, 5, 6}));
}

TEST(ExposedSystem, NothingChangesWithoutPartlyExposedOrBuriedReflectors) {
    // Exposed, and buried but black.
    RadiositySystem system = makeSystem(2, 1, {diagonalOperator({0.5}), diagonalOperator({0})});
    system.patchOperator = {0, 1};
    const ExposedSystem exposed =
        exposedSystem(system, std::vector<float>{1.0f, 0.0f}, std::vector<double>{1.0, 0.0});
    EXPECT_FALSE(exposed.changed);
    EXPECT_EQ(exposed.phi, (std::vector<double>{1, 1}));
}

}  // namespace
}  // namespace daisy
