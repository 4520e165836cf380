#include "bench/chart.h"

#include <stb/stb_easy_font.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace daisy {
namespace {

using Colour = std::array<uint8_t, 3>;

// Okabe & Ito 2008, "Color Universal Design" palette (distinguishable with colour-vision
// deficiencies), then three greys-to-browns for series beyond it.
constexpr Colour kPalette[] = {{0, 114, 178},  {230, 159, 0}, {0, 158, 115},  {204, 121, 167},
                               {86, 180, 233}, {213, 94, 0},  {240, 228, 66}, {120, 120, 120},
                               {140, 86, 75},  {0, 0, 0}};
constexpr Colour kBlack{0, 0, 0};
constexpr Colour kGrid{225, 225, 225};
constexpr Colour kAxis{60, 60, 60};
constexpr Colour kReference{200, 30, 30};
constexpr int kTextScale = 2;  // stb_easy_font glyphs are ~7 px tall; twice that reads well

class Canvas {
public:
    explicit Canvas(int width, int height) {
        image_.width = width;
        image_.height = height;
        image_.pixels.assign(std::size_t(width) * height * 3, 255);
    }
    Rgb8Image take() { return std::move(image_); }

    void pixel(int x, int y, Colour c) {
        if (x < 0 || y < 0 || x >= image_.width || y >= image_.height) return;
        uint8_t* p = &image_.pixels[(std::size_t(y) * image_.width + x) * 3];
        p[0] = c[0], p[1] = c[1], p[2] = c[2];
    }
    void rect(int x0, int y0, int x1, int y1, Colour c) {
        for (int y = std::min(y0, y1); y <= std::max(y0, y1); ++y)
            for (int x = std::min(x0, x1); x <= std::max(x0, x1); ++x)
                pixel(x, y, c);
    }
    // A line `thickness` pixels wide; dashed when dash > 0 (on and off runs of `dash` pixels).
    void line(double x0, double y0, double x1, double y1, Colour c, int thickness = 1,
              int dash = 0) {
        const double length = std::hypot(x1 - x0, y1 - y0);
        const int steps = std::max(1, int(std::ceil(length)));
        const int half = thickness / 2;
        for (int s = 0; s <= steps; ++s) {
            if (dash > 0 && (s / dash) % 2 == 1) continue;
            const double t = double(s) / steps;
            const int x = int(std::lround(x0 + (x1 - x0) * t));
            const int y = int(std::lround(y0 + (y1 - y0) * t));
            rect(x - half, y - half, x - half + thickness - 1, y - half + thickness - 1, c);
        }
    }
    void disc(double cx, double cy, double radius, Colour c) {
        const int r = int(std::ceil(radius));
        for (int dy = -r; dy <= r; ++dy)
            for (int dx = -r; dx <= r; ++dx)
                if (dx * dx + dy * dy <= radius * radius)
                    pixel(int(std::lround(cx)) + dx, int(std::lround(cy)) + dy, c);
    }
    void circle(double cx, double cy, double radius, Colour c) {
        for (int a = 0; a < 64; ++a) {
            const double t0 = a * 2 * M_PI / 64, t1 = (a + 1) * 2 * M_PI / 64;
            line(cx + radius * std::cos(t0), cy + radius * std::sin(t0), cx + radius * std::cos(t1),
                 cy + radius * std::sin(t1), c, 2);
        }
    }
    static int textWidth(const std::string& text) {
        std::string copy = text;
        return stb_easy_font_width(copy.data()) * kTextScale;
    }
    static int textHeight() { return 7 * kTextScale; }
    // Text with its top-left corner at (x, y).
    void text(int x, int y, const std::string& text, Colour c) {
        std::string copy = text;
        static thread_local std::vector<char> buffer(1 << 18);
        const int quads =
            stb_easy_font_print(0, 0, copy.data(), nullptr, buffer.data(), int(buffer.size()));
        for (int q = 0; q < quads; ++q) {
            const float* v0 = reinterpret_cast<const float*>(buffer.data() + q * 64);
            const float* v2 = reinterpret_cast<const float*>(buffer.data() + q * 64 + 32);
            rect(x + int(v0[0] * kTextScale), y + int(v0[1] * kTextScale),
                 x + int(v2[0] * kTextScale) - 1, y + int(v2[1] * kTextScale) - 1, c);
        }
    }
    // Text rotated 90 degrees counter-clockwise, reading upwards, its centre at (cx, cy).
    void verticalText(int cx, int cy, const std::string& label, Colour c) {
        Canvas strip(textWidth(label) + 2, textHeight() + 2);
        strip.text(1, 1, label, c);
        const Rgb8Image& s = strip.image_;
        for (int y = 0; y < s.height; ++y)
            for (int x = 0; x < s.width; ++x) {
                const uint8_t* p = &s.pixels[(std::size_t(y) * s.width + x) * 3];
                if (p[0] == 255 && p[1] == 255 && p[2] == 255) continue;
                pixel(cx - s.height / 2 + y, cy + s.width / 2 - x, {p[0], p[1], p[2]});
            }
    }

private:
    Rgb8Image image_;
};

bool usable(const ChartPoint& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && p.x > 0 && p.y > 0;
}

std::string decadeLabel(int exponent) {
    if (exponent >= 0 && exponent <= 4) {
        char text[16];
        std::snprintf(text, sizeof text, "%.0f", std::pow(10.0, exponent));
        return text;
    }
    if (exponent < 0 && exponent >= -3) {
        char text[16];
        std::snprintf(text, sizeof text, "%.*f", -exponent, std::pow(10.0, exponent));
        return text;
    }
    return "1e" + std::to_string(exponent);
}

}  // namespace

std::vector<int> paretoFront(const std::vector<ChartPoint>& points) {
    std::vector<int> order;
    for (int k = 0; k < int(points.size()); ++k)
        if (usable(points[k])) order.push_back(k);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        return points[a].x != points[b].x ? points[a].x < points[b].x : points[a].y < points[b].y;
    });
    std::vector<int> front;
    double bestY = INFINITY;
    for (int k : order) {
        if (points[k].y < bestY) {
            front.push_back(k);
            bestY = points[k].y;
        }
    }
    return front;
}

Rgb8Image drawLogLogChart(const ChartSpec& spec) {
    Canvas canvas(spec.width, spec.height);
    const int legendWidth = 230;
    const int left = 100, right = spec.width - legendWidth, top = 60, bottom = spec.height - 80;

    double xMin = INFINITY, xMax = -INFINITY, yMin = INFINITY, yMax = -INFINITY;
    for (const ChartPoint& p : spec.points) {
        if (!usable(p)) continue;
        xMin = std::min(xMin, p.x), xMax = std::max(xMax, p.x);
        yMin = std::min(yMin, p.y), yMax = std::max(yMax, p.y);
    }
    if (spec.referenceY > 0)
        yMin = std::min(yMin, spec.referenceY), yMax = std::max(yMax, spec.referenceY);
    if (!(xMin <= xMax)) xMin = 0.1, xMax = 10;
    if (!(yMin <= yMax)) yMin = 0.1, yMax = 10;
    const int ex0 = int(std::floor(std::log10(xMin))), ex1 = int(std::ceil(std::log10(xMax)));
    const int ey0 = int(std::floor(std::log10(yMin))), ey1 = int(std::ceil(std::log10(yMax)));
    const double lx0 = ex0, lx1 = std::max(ex1, ex0 + 1);
    const double ly0 = ey0, ly1 = std::max(ey1, ey0 + 1);
    const auto px = [&](double x) {
        return left + (std::log10(x) - lx0) / (lx1 - lx0) * (right - left);
    };
    const auto py = [&](double y) {
        return bottom - (std::log10(y) - ly0) / (ly1 - ly0) * (bottom - top);
    };

    // Grid: decades solid, 2..9 lighter.
    for (int e = int(lx0); e <= int(lx1); ++e) {
        for (int m = 1; m <= 9 && (m == 1 || e < int(lx1)); ++m) {
            const double x = px(m * std::pow(10.0, e));
            canvas.line(x, top, x, bottom, m == 1 ? kGrid : Colour{242, 242, 242});
        }
        const std::string label = decadeLabel(e);
        canvas.text(int(px(std::pow(10.0, e))) - Canvas::textWidth(label) / 2, bottom + 10, label,
                    kAxis);
    }
    for (int e = int(ly0); e <= int(ly1); ++e) {
        for (int m = 1; m <= 9 && (m == 1 || e < int(ly1)); ++m) {
            const double y = py(m * std::pow(10.0, e));
            canvas.line(left, y, right, y, m == 1 ? kGrid : Colour{242, 242, 242});
        }
        const std::string label = decadeLabel(e);
        canvas.text(left - 10 - Canvas::textWidth(label), int(py(std::pow(10.0, e))) - 7, label,
                    kAxis);
    }
    canvas.line(left, bottom, right, bottom, kAxis, 2);
    canvas.line(left, top, left, bottom, kAxis, 2);

    if (spec.referenceY > 0) {
        const double y = py(spec.referenceY);
        canvas.line(left, y, right, y, kReference, 2, 8);
        canvas.text(right - Canvas::textWidth(spec.referenceLabel) - 4, int(y) - 20,
                    spec.referenceLabel, kReference);
    }
    for (std::size_t k = 1; k < spec.front.size(); ++k) {
        const ChartPoint& a = spec.points[spec.front[k - 1]];
        const ChartPoint& b = spec.points[spec.front[k]];
        canvas.line(px(a.x), py(a.y), px(b.x), py(b.y), kBlack, 2);
    }
    std::vector<bool> onFront(spec.points.size(), false);
    for (int k : spec.front)
        onFront[k] = true;
    // Labels beside their points: the first of right-above, right-below, left-above, left-below
    // that overlaps no label (or marker) placed before, else stacked below the first choice.
    struct Box {
        int x0, y0, x1, y1;
    };
    std::vector<Box> placed;
    if (spec.referenceY > 0) {
        const int w = Canvas::textWidth(spec.referenceLabel);
        const int y = int(py(spec.referenceY)) - 20;
        placed.push_back({right - w - 4, y, right, y + Canvas::textHeight()});
    }
    for (const ChartPoint& p : spec.points)
        if (usable(p))
            placed.push_back(
                {int(px(p.x)) - 7, int(py(p.y)) - 7, int(px(p.x)) + 7, int(py(p.y)) + 7});
    const auto overlaps = [&](const Box& b) {
        for (const Box& o : placed)
            if (b.x0 < o.x1 && o.x0 < b.x1 && b.y0 < o.y1 && o.y0 < b.y1) return true;
        return false;
    };
    for (std::size_t k = 0; k < spec.points.size(); ++k) {
        const ChartPoint& p = spec.points[k];
        if (!usable(p)) continue;
        const Colour c = kPalette[std::size_t(p.series) % std::size(kPalette)];
        canvas.disc(px(p.x), py(p.y), 6, c);
        if (onFront[k]) canvas.circle(px(p.x), py(p.y), 9, kBlack);
    }
    for (const ChartPoint& p : spec.points) {
        if (!usable(p) || p.label.empty()) continue;
        const int w = Canvas::textWidth(p.label), h = Canvas::textHeight();
        const int x = int(px(p.x)), y = int(py(p.y));
        // Rings of candidates moving away from the point a line at a time; a label placed away
        // from its point gets a thin leader line.
        Box box{x + 11, y - 16, x + 11 + w, y - 16 + h};
        int ring = 0;
        bool found = false;
        for (; ring < 12 && !found; ++ring) {
            const int shift = ring * (h + 4);
            const Box candidates[] = {{x + 11, y - 16 - shift, x + 11 + w, y - 16 - shift + h},
                                      {x + 11, y + 4 + shift, x + 11 + w, y + 4 + shift + h},
                                      {x - 11 - w, y - 16 - shift, x - 11, y - 16 - shift + h},
                                      {x - 11 - w, y + 4 + shift, x - 11, y + 4 + shift + h}};
            for (const Box& candidate : candidates) {
                if (candidate.x0 < left || candidate.y0 < top || candidate.y1 > bottom ||
                    overlaps(candidate))
                    continue;
                box = candidate;
                found = true;
                break;
            }
        }
        if (found && ring > 1) {
            const double lx = box.x0 > x ? box.x0 - 2 : box.x1 + 2;
            const double ly = box.y0 > y ? box.y0 : box.y1;
            canvas.line(x, y, lx, ly, {150, 150, 150}, 1);
        }
        placed.push_back(box);
        canvas.text(box.x0, box.y0, p.label, {40, 40, 40});
    }

    canvas.text((left + right - Canvas::textWidth(spec.title)) / 2, 18, spec.title, kBlack);
    canvas.text((left + right - Canvas::textWidth(spec.xLabel)) / 2, bottom + 42, spec.xLabel,
                kBlack);
    canvas.verticalText(30, (top + bottom) / 2, spec.yLabel, kBlack);

    int ly = top;
    for (std::size_t s = 0; s < spec.seriesNames.size(); ++s, ly += 28) {
        canvas.disc(right + 30, ly + 7, 6, kPalette[s % std::size(kPalette)]);
        canvas.text(right + 44, ly, spec.seriesNames[s], kBlack);
    }
    canvas.circle(right + 30, ly + 7, 9, kBlack);
    canvas.text(right + 44, ly, "Pareto front", kBlack);
    return canvas.take();
}

}  // namespace daisy
