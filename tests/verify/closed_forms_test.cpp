// The closed forms of verify/closed_forms.h against the values tabulated in J. R. Howell, "A
// Catalog of Radiation Heat Transfer Configuration Factors", 3rd ed. (C-11: 0.199824895698 for
// unit squares at distance 1, 0.0685895888185526 at distance 2; C-14: 0.200043776075 for unit
// squares sharing an edge), their limits (a point under an infinite plane's corner sees a
// quarter of the hemisphere: B-3 -> 1/4; far apart, F -> A / (pi d^2)) and reciprocity
// (Howell, Menguc & Siegel, "Thermal Radiation Heat Transfer", 6th ed., eq. 4.20).
#include "verify/closed_forms.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

namespace daisy::verify {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(ClosedForms, ParallelRectanglesMatchHowellC11) {
    EXPECT_NEAR(parallelRectangles(1, 1, 1), 0.199824895698, 1e-12);
    EXPECT_NEAR(parallelRectangles(1, 1, 1), kHowellC11, 1e-12);
    EXPECT_NEAR(parallelRectangles(1, 1, 2), kHowellC11Distance2, 1e-14);
    // Dimensionless: only a / c and b / c matter; symmetric in a and b.
    EXPECT_NEAR(parallelRectangles(3, 3, 3), kHowellC11, 1e-12);
    EXPECT_NEAR(parallelRectangles(2, 0.5, 1.5), parallelRectangles(0.5, 2, 1.5), 1e-15);
    // Far apart: F -> A_j / (pi c^2) (the point-to-point kernel at normal incidence), with a
    // relative correction of O(1 / c^2): 6.7e-5 at c = 100.
    EXPECT_NEAR(parallelRectangles(1, 1, 100) * kPi * 1e4, 1, 1e-4);
    // Nearly touching: F -> 1.
    EXPECT_NEAR(parallelRectangles(1, 1, 1e-6), 1, 1e-5);
}

TEST(ClosedForms, PerpendicularRectanglesMatchHowellC14) {
    EXPECT_NEAR(perpendicularRectangles(1, 1, 1), 0.200043776075, 1e-12);
    EXPECT_NEAR(perpendicularRectangles(1, 1, 1), kHowellC14, 1e-12);
    EXPECT_NEAR(perpendicularRectangles(2, 2, 2), kHowellC14, 1e-12);
    // Reciprocity: A_w F_wh = A_h F_hw with A_w = w l, A_h = h l.
    const double w = 0.7, h = 2.3, l = 1.4;
    EXPECT_NEAR(w * l * perpendicularRectangles(w, h, l), h * l * perpendicularRectangles(h, w, l),
                1e-14);
    // A long floor strip under a very high wall: the 2D crossed-strings limit (Hottel)
    // (w + h - sqrt(w^2 + h^2)) / (2 w) -> 1/2 as h and l grow.
    EXPECT_NEAR(perpendicularRectangles(1, 1e6, 1e6), 0.5, 1e-5);
}

TEST(ClosedForms, PointToRectangleCornerIsHowellB3) {
    // B-3 at A = B = 1 (the catalogue formula evaluated in double).
    EXPECT_NEAR(pointToRectangleCorner(1, 1, 1), 0.138531605994893, 1e-14);
    EXPECT_NEAR(pointToRectangleCorner(2, 3, 2), pointToRectangleCorner(1, 1.5, 1), 1e-15);
    // An infinite quadrant under the point: a quarter of the hemisphere.
    EXPECT_NEAR(pointToRectangleCorner(1e9, 1e9, 1), 0.25, 1e-9);
}

TEST(ClosedForms, PointToPolygonAgreesWithB3) {
    // Lambert's contour formula for the unit square one unit above a corner, either winding.
    const std::array<Vec3d, 4> square = {Vec3d{0, 0, 1}, Vec3d{1, 0, 1}, Vec3d{1, 1, 1},
                                         Vec3d{0, 1, 1}};
    const std::array<Vec3d, 4> reversed = {square[3], square[2], square[1], square[0]};
    EXPECT_NEAR(pointToPolygon({0, 0, 0}, {0, 0, 1}, square), pointToRectangleCorner(1, 1, 1),
                1e-14);
    EXPECT_NEAR(pointToPolygon({0, 0, 0}, {0, 0, 1}, reversed), pointToRectangleCorner(1, 1, 1),
                1e-14);
}

TEST(ClosedForms, HingedSquaresAtRightAngleIsHowellC14) {
    EXPECT_NEAR(hingedSquares(kPi / 2), kHowellC14, 1e-9);
    // Opening the hinge sees less: F falls from 1 (folded shut) towards 0 (flat).
    EXPECT_GT(hingedSquares(kPi / 4), hingedSquares(kPi / 2));
    EXPECT_GT(hingedSquares(kPi / 2), hingedSquares(3 * kPi / 4));
}

TEST(ClosedForms, SmallSquareToPlaneIsFourCornersOfB3) {
    // A vanishing square is its centre point: four B-3 corners of 1 x 1 rectangles.
    EXPECT_NEAR(smallSquareToPlane(1e-6, 0.5), 4 * pointToRectangleCorner(1, 1, 0.5), 1e-12);
    // Averaging over a finite square lowers the factor (the centre sees the most).
    EXPECT_LT(smallSquareToPlane(0.5, 0.5), 4 * pointToRectangleCorner(1, 1, 0.5));
}

}  // namespace
}  // namespace daisy::verify
