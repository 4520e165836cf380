#pragma once
// Closed-form view factors and double-precision oracles shared by the tests, the tools and
// `daisy bench --stress`. Catalogue cases are from J. R. Howell, "A Catalog of Radiation Heat
// Transfer Configuration Factors", 3rd ed. (http://www.thermalradiation.net/indexCat.html).
// Lengths in any one unit (the factors are dimensionless); angles in radians.
#include <span>

#include "geometry/vec3.h"

namespace daisy::verify {

// Howell C-11, identical parallel directly opposed unit squares at distance 1 (X = Y = 1).
inline constexpr double kHowellC11 = 0.199824895698;
// Howell C-11, the same unit squares at distance 2 (X = Y = 0.5).
inline constexpr double kHowellC11Distance2 = 0.0685895888185526;
// Howell C-14, perpendicular unit squares sharing an edge (H = W = 1).
inline constexpr double kHowellC14 = 0.200043776075;

// Howell C-11: F between identical parallel directly opposed rectangles a x b at distance c.
double parallelRectangles(double a, double b, double c);

// Howell C-14: F from the rectangle w x l to the rectangle h x l sharing its edge of length l at
// 90 degrees.
double perpendicularRectangles(double w, double h, double l);

// Howell B-3: F from a differential area at height h above a corner of an a x b rectangle,
// parallel to it and facing it.
double pointToRectangleCorner(double a, double b, double h);

// Lambert's contour formula in double: F from a differential area at p (unit normal n) to a
// convex polygon entirely in front of it (Baum et al. 1989, as shared/formfactor.h).
double pointToPolygon(const Vec3d& p, const Vec3d& n, std::span<const Vec3d> polygon);

// F from the unit square (s, t) in [0, 1]^2 at z = 0 (normal +z) to the unit square hinged on
// the shared edge t = 0 at included angle phi, by 12-point Gauss-Legendre on graded panels of
// pointToPolygon; within 1e-9 of Howell C-14 at phi = pi / 2 (closed_forms_test).
double hingedSquares(double phi);

// F from a square of side `side` centred at height h above the centre of the square [-1, 1]^2,
// parallel and facing it: Howell B-3 summed over the four corner rectangles, averaged over the
// small square by 12 x 12 Gauss-Legendre points.
double smallSquareToPlane(double side, double h);

}  // namespace daisy::verify
