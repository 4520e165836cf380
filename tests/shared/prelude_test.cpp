// The portable dialect's own math (shared/prelude.h). Oracles: the double-precision C library
// (std::atan2 is correctly rounded to well below a float ulp, so its value rounded to float is
// the exact answer here), and the IEEE semantics of min/max the kernels rely on.
#include "shared/prelude.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace daisy::shared {
namespace {

// Relative error of daisyAtan2(y, x) against the double atan2; below the smallest normal float
// (|y / x| under 1e-38, where a float result cannot be relative-accurate) the error is taken
// relative to that.
double atanError(float y, float x) {
    const double exact = std::atan2(double(y), double(x));
    const double got = double(daisyAtan2(y, x));
    return std::fabs(got - exact) /
        std::max(std::fabs(exact), double(std::numeric_limits<float>::min()));
}

// Over the whole circle at every scale: random directions and magnitudes from 1e-30 to 1e30
// (independently for y and x, so the ratio spans far past the float range of tan), against the
// documented bound of 2.5e-7 relative (about 2 ULP).
TEST(PreludeAtan2, MatchesTheCLibraryOverTheWholeRange) {
    std::mt19937 rng(18);
    std::uniform_real_distribution<double> exponent(-30.0, 30.0);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI);
    double worst = 0.0;
    for (int k = 0; k < 400000; ++k) {
        const double t = angle(rng);
        const float y = float(std::sin(t) * std::pow(10.0, exponent(rng)));
        const float x = float(std::cos(t) * std::pow(10.0, exponent(rng)));
        worst = std::max(worst, atanError(y, x));
    }
    // Near the octant boundaries, where the reduction switches (|y| / |x| = tan(pi/8), 1).
    for (float ratio : {0.414213562f, 0.41421354f, 0.41421357f, 1.0f, 0.99999994f, 1.0000001f}) {
        for (float sx : {1.0f, -1.0f}) {
            for (float sy : {1.0f, -1.0f}) {
                worst = std::max(worst, atanError(sy * ratio, sx));
                worst = std::max(worst, atanError(sy, sx * ratio));
            }
        }
    }
    EXPECT_LT(worst, 2.5e-7);
}

// The angle as the view-factor kernel asks for it (y = |v x e| >= 0, x = v . w): small angles
// between nearly parallel vectors keep their relative accuracy, which the contour sum needs.
TEST(PreludeAtan2, SmallAnglesKeepRelativeAccuracy) {
    for (float y = 1e-20f; y < 1e-2f; y *= 3.7f) {
        EXPECT_LT(atanError(y, 1.0f), 2.5e-7) << y;
        EXPECT_LT(atanError(y, -1.0f), 2.5e-7) << y;
        EXPECT_LT(atanError(1.0f, y), 2.5e-7) << y;
    }
}

TEST(PreludeAtan2, AxesZerosAndExtremes) {
    const float pi = float(M_PI);
    EXPECT_EQ(daisyAtan2(0.0f, 1.0f), 0.0f);
    EXPECT_EQ(daisyAtan2(0.0f, 0.0f), 0.0f);
    EXPECT_EQ(daisyAtan2(0.0f, -2.0f), pi);
    EXPECT_EQ(daisyAtan2(3.0f, 0.0f), float(M_PI / 2));
    EXPECT_EQ(daisyAtan2(-3.0f, 0.0f), -float(M_PI / 2));
    EXPECT_EQ(daisyAtan2(-0.0f, 1.0f), 0.0f);
    EXPECT_EQ(daisyAtan2(1.0f, 1.0f), float(M_PI / 4));
    EXPECT_EQ(daisyAtan2(-1.0f, -1.0f), -float(3 * M_PI / 4));
    const float big = std::numeric_limits<float>::max();
    const float tiny = std::numeric_limits<float>::denorm_min();
    EXPECT_LT(atanError(big, big), 2.5e-7);  // m + M overflows to inf: still pi/4
    EXPECT_LT(atanError(-big, big), 2.5e-7);
    EXPECT_LT(atanError(tiny, 1.0f), 2.5e-7);
    EXPECT_LT(atanError(1.0f, big), 2.5e-7);
    EXPECT_LT(atanError(big, -tiny), 2.5e-7);
    EXPECT_LT(atanError(tiny, tiny), 2.5e-7);
    // The atan(y, x) the shared code writes is this function in C++ too.
    EXPECT_EQ(atan(0.3f, -0.7f), daisyAtan2(0.3f, -0.7f));
}

// min/max are compare-and-select: the first argument wins on NaN, so the kernels' clamps
// (max(0.0f, x), min(1.0f, x)) turn a NaN into the constant, as fmaxf/fminf do.
TEST(PreludeMinMax, ValuesAndNaN) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(max(1.0f, 2.0f), 2.0f);
    EXPECT_EQ(max(2.0f, 1.0f), 2.0f);
    EXPECT_EQ(min(1.0f, 2.0f), 1.0f);
    EXPECT_EQ(min(-1.0f, -2.0f), -2.0f);
    EXPECT_EQ(max(0.0f, nan), 0.0f);
    EXPECT_EQ(min(1.0f, nan), 1.0f);
    EXPECT_EQ(clamp(nan, 0.0f, 1.0f), 0.0f);
    EXPECT_EQ(clamp(-3.0f, 0.0f, 1.0f), 0.0f);
    EXPECT_EQ(clamp(0.25f, 0.0f, 1.0f), 0.25f);
}

}  // namespace
}  // namespace daisy::shared
