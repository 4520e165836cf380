// The bench plot's Pareto front (by definition: no other point is both faster and more accurate)
// and the chart's drawing of it.
#include "bench/chart.h"

#include <gtest/gtest.h>

#include <cmath>

namespace daisy {
namespace {

ChartPoint point(double x, double y, int series = 0) {
    ChartPoint p;
    p.x = x;
    p.y = y;
    p.series = series;
    return p;
}

TEST(ParetoFront, KeepsExactlyTheUndominatedPointsSortedByX) {
    // (3, 3) is dominated by (2, 2); (5, 2) by (2, 2) (same y, slower); NaN and 0 never count.
    const std::vector<ChartPoint> points = {point(1, 5),   point(3, 3),    point(2, 2),
                                            point(5, 2),   point(10, 0.5), point(NAN, 0.1),
                                            point(0, 0.01)};
    EXPECT_EQ(paretoFront(points), (std::vector<int>{0, 2, 4}));
}

TEST(ParetoFront, EmptyAndSinglePoint) {
    EXPECT_TRUE(paretoFront({}).empty());
    EXPECT_EQ(paretoFront({point(1, 1)}), (std::vector<int>{0}));
}

TEST(LogLogChart, DrawsEveryPointInItsSeriesColour) {
    ChartSpec spec;
    spec.title = "t";
    spec.seriesNames = {"a", "b"};
    spec.points = {point(0.5, 2, 0), point(20, 0.3, 1)};
    spec.front = paretoFront(spec.points);
    spec.referenceY = 1;
    const Rgb8Image image = drawLogLogChart(spec);
    ASSERT_EQ(image.width, spec.width);
    ASSERT_EQ(image.height, spec.height);
    ASSERT_EQ(image.pixels.size(), std::size_t(image.width) * image.height * 3);
    // Series 0 is Okabe-Ito blue (0, 114, 178), series 1 orange (230, 159, 0): both drawn.
    int blue = 0, orange = 0;
    for (std::size_t p = 0; p < image.pixels.size(); p += 3) {
        blue += image.pixels[p] == 0 && image.pixels[p + 1] == 114 && image.pixels[p + 2] == 178;
        orange += image.pixels[p] == 230 && image.pixels[p + 1] == 159 && image.pixels[p + 2] == 0;
    }
    EXPECT_GT(blue, 2 * 100);  // two discs of radius 6 (one in the legend), ~113 pixels each
    EXPECT_GT(orange, 2 * 100);
}

}  // namespace
}  // namespace daisy
