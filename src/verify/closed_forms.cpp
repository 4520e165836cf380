#include "verify/closed_forms.h"

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace daisy::verify {
namespace {

constexpr double kPi = std::numbers::pi;

// Gauss-Legendre nodes and weights on [0, 1], 12 points (Abramowitz & Stegun 25.4.30 table).
struct GaussRule {
    std::array<double, 12> x{}, w{};
    GaussRule() {
        const int n = 12;
        for (int i = 0; i < n; ++i) {  // Newton on P_n from the Chebyshev guess
            double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), pp = 0;
            for (int it = 0; it < 100; ++it) {
                double p1 = 1, p2 = 0;
                for (int j = 1; j <= n; ++j) {
                    const double p3 = p2;
                    p2 = p1;
                    p1 = ((2 * j - 1) * z * p2 - (j - 1) * p3) / j;
                }
                pp = n * (z * p1 - p2) / (z * z - 1);
                const double dz = p1 / pp;
                z -= dz;
                if (std::abs(dz) < 1e-16) break;
            }
            x[i] = 0.5 * (1 - z);
            w[i] = 1 / ((1 - z * z) * pp * pp);
        }
    }
};

// Panels of [0, 1] graded geometrically toward both ends (ratio 1/2 down to 2^-depth), for
// integrands with endpoint singularities in their derivatives.
std::vector<double> gradedBreaks(int depth, bool bothEnds) {
    std::vector<double> breaks{0};
    for (int k = depth; k >= 1; --k)
        breaks.push_back(std::ldexp(bothEnds ? 0.5 : 1.0, -k));
    if (!bothEnds) {
        breaks.push_back(1);
        return breaks;
    }
    for (int k = 1; k <= depth; ++k)
        breaks.push_back(1 - std::ldexp(0.5, -k));
    breaks.push_back(1);
    return breaks;
}

}  // namespace

double parallelRectangles(double a, double b, double c) {
    const double x = a / c, y = b / c;
    const double x1 = std::sqrt(1 + x * x), y1 = std::sqrt(1 + y * y);
    const double bracket = 0.5 * std::log((1 + x * x) * (1 + y * y) / (1 + x * x + y * y)) +
        x * y1 * std::atan(x / y1) + y * x1 * std::atan(y / x1) - x * std::atan(x) -
        y * std::atan(y);
    return 2 / (kPi * x * y) * bracket;
}

double perpendicularRectangles(double w, double h, double l) {
    const double W = w / l, H = h / l, w2 = W * W, h2 = H * H, s = w2 + h2;
    const double logTerm = std::log((1 + w2) * (1 + h2) / (1 + s)) +
        w2 * std::log(w2 * (1 + s) / ((1 + w2) * s)) + h2 * std::log(h2 * (1 + s) / ((1 + h2) * s));
    return (W * std::atan(1 / W) + H * std::atan(1 / H) -
            std::sqrt(s) * std::atan(1 / std::sqrt(s)) + 0.25 * logTerm) /
        (kPi * W);
}

double pointToRectangleCorner(double a, double b, double h) {
    const double A = a / h, B = b / h, a1 = std::sqrt(1 + A * A), b1 = std::sqrt(1 + B * B);
    return (A / a1 * std::atan(B / a1) + B / b1 * std::atan(A / b1)) / (2 * kPi);
}

double pointToPolygon(const Vec3d& p, const Vec3d& n, std::span<const Vec3d> polygon) {
    double sum = 0;
    for (std::size_t k = 0; k < polygon.size(); ++k) {
        const Vec3d vk = polygon[k] - p, vk1 = polygon[(k + 1) % polygon.size()] - p;
        const Vec3d g = cross(vk, vk1);
        const double gl = length(g);
        if (gl > 0) sum += std::atan2(gl, dot(vk, vk1)) * dot(n, g) / gl;
    }
    return std::abs(sum) / (2 * kPi);
}

double hingedSquares(double phi) {
    static const GaussRule rule;
    const Vec3d n{0, 0, 1};
    const std::array<Vec3d, 4> other = {Vec3d{0, 0, 0}, Vec3d{0, std::cos(phi), std::sin(phi)},
                                        Vec3d{1, std::cos(phi), std::sin(phi)}, Vec3d{1, 0, 0}};
    const std::vector<double> sBreaks = gradedBreaks(24, true), tBreaks = gradedBreaks(40, false);
    double total = 0;
    for (std::size_t a = 0; a + 1 < sBreaks.size(); ++a) {
        for (std::size_t b = 0; b + 1 < tBreaks.size(); ++b) {
            const double s0 = sBreaks[a], ds = sBreaks[a + 1] - s0;
            const double t0 = tBreaks[b], dt = tBreaks[b + 1] - t0;
            for (int i = 0; i < 12; ++i)
                for (int j = 0; j < 12; ++j)
                    total += rule.w[i] * rule.w[j] * ds * dt *
                        pointToPolygon({s0 + ds * rule.x[i], t0 + dt * rule.x[j], 0}, n, other);
        }
    }
    return total;
}

double smallSquareToPlane(double side, double h) {
    static const GaussRule rule;
    double total = 0;
    for (int i = 0; i < 12; ++i) {
        for (int j = 0; j < 12; ++j) {
            const double x = side * (rule.x[i] - 0.5), y = side * (rule.x[j] - 0.5);
            const double f = pointToRectangleCorner(1 - x, 1 - y, h) +
                pointToRectangleCorner(1 + x, 1 - y, h) + pointToRectangleCorner(1 - x, 1 + y, h) +
                pointToRectangleCorner(1 + x, 1 + y, h);
            total += rule.w[i] * rule.w[j] * f;
        }
    }
    return total;
}

}  // namespace daisy::verify
