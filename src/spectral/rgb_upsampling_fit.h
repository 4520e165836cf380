#pragma once
// The optimiser behind the RGB -> spectrum table (as in Jakob & Hanika 2019): for each
// table node, Gauss-Newton on the three sigmoid-polynomial coefficients, minimising the CIELAB
// difference between the target linear-sRGB colour and the colour of s(l) as a reflectance
// under D65. The colour of a spectrum is the sum over the 1 nm CIE 1931 table of
// s(l) D65(l) {xbar, ybar, zbar}(l), D65 interpolated linearly from its 5 nm CIE table, divided
// by the same sum for s = 1. The target XYZ of an RGB uses the sRGB primaries balanced to that
// white (the CIE D65 spectrum's, x = 0.31273, y = 0.32902) rather than to the rounded IEC
// 61966-2-1 white (0.3127, 0.3290): then RGB (1, 1, 1) is exactly the perfect reflector s = 1 and
// every colour in the cube is reachable; the two whites differ by 3e-5 in x and y, an RGB
// difference under 3e-4 (docs/spectral.md). tools/make_rgb_table writes the committed table.
#include <array>
#include <cstddef>
#include <vector>

#include "spectral/color.h"
#include "spectral/rgb_upsampling.h"

namespace daisy {

class SigmoidFitter {
public:
    SigmoidFitter();

    struct Result {
        std::array<double, 3> coefficients{0, 0, 0};
        double residualLab = 0;  // Delta E*ab between target and fitted colour
        int iterations = 0;
    };

    // Fits the coefficients for `target` (linear sRGB, each in [0, 1]) from `start`.
    Result fit(const Rgb& target, const std::array<double, 3>& start) const;

    // The colour of a sigmoid-polynomial reflectance under D65 as the fit measures it.
    Xyz reflectanceXyz(const SigmoidPolynomial& shape) const;
    // The XYZ the fit aims at for a linear-sRGB colour (see above).
    Xyz targetXyz(const Rgb& rgb) const;
    const Xyz& whiteXyz() const { return white_; }

private:
    // Colour and its Jacobian with respect to the coefficients.
    Xyz evaluate(const std::array<double, 3>& c, Matrix3* jacobian) const;

    std::vector<std::array<double, 3>> weights_;  // per nm: D65 * cmf / sum(D65 * ybar)
    std::vector<double> u_;  // normalised wavelength per nm
    Xyz white_{};
    Matrix3 targetMatrix_{};
};

// Residuals (Delta E*ab) over the nodes fitted by Gauss-Newton (not the closed-form ones).
struct RgbTableFitStats {
    std::size_t fittedNodes = 0;
    std::size_t closedFormNodes = 0;  // black and grey nodes
    double maxResidualLab = 0;
    double meanResidualLab = 0;
    std::size_t nodesAboveTolerance = 0;  // residual > kFitToleranceLab
    double seconds = 0;
};

// Gauss-Newton stops below this Delta E*ab.
inline constexpr double kFitToleranceLab = 1e-6;

// Fits a table of `resolution` (>= 2) nodes per axis. As in the paper, each (l, x, y) column
// starts at z node resolution / 5 from the previous x node's solution there (0 at x = 0), then
// walks up and down in z, each node starting from its fitted neighbour (and from 0 if that
// fails). Black (z = 0) and grey (x = y = 1) nodes are constant spectra in closed form, held
// 1e-4 inside (0, 1): black and white themselves need infinite coefficients. Rows run in
// parallel; the result does not depend on the thread count.
RgbToSpectrumTable fitRgbToSpectrumTable(int resolution, RgbTableFitStats* stats = nullptr);

}  // namespace daisy
