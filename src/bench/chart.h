#pragma once
// A log-log scatter chart drawn straight into 8-bit RGB pixels, for `daisy bench`'s "error
// against time" plot: points coloured by series, a polyline through the Pareto front, a dashed
// horizontal reference line (the just-noticeable difference), decade grid, labels and a legend.
// Text is stb_easy_font's vector font (public domain, Sean Barrett), drawn at twice its size.
#include <cstdint>
#include <string>
#include <vector>

namespace daisy {

struct ChartPoint {
    double x = 0;  // > 0 (log axis); points with x or y <= 0 or not finite are left out
    double y = 0;  // > 0
    int series = 0;  // index into ChartSpec::seriesNames, picks the colour
    std::string label;  // drawn beside the point when non-empty
};

struct ChartSpec {
    std::string title;
    std::string xLabel;
    std::string yLabel;
    std::vector<std::string> seriesNames;  // legend entries, at most 10 distinct colours
    std::vector<ChartPoint> points;
    std::vector<int> front;  // indices into points, joined in order by a black polyline
    double referenceY = 0;  // > 0: dashed horizontal line at this y
    std::string referenceLabel;
    int width = 1100;
    int height = 700;
};

struct Rgb8Image {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> pixels;  // width * height * 3, top row first
};

Rgb8Image drawLogLogChart(const ChartSpec& spec);

// Indices of the Pareto-optimal points (no other point has both x <= and y <= with one strict),
// sorted by increasing x. Non-finite or non-positive points never qualify.
std::vector<int> paretoFront(const std::vector<ChartPoint>& points);

}  // namespace daisy
