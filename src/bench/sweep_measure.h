#pragma once
// The settings sweep's error measurement (bench/sweep.h), internal to src/bench/.
#include <vector>

#include "bench/sweep.h"
#include "geometry/patch_mesh.h"
#include "image/image.h"
#include "spectral/wavelength_set.h"

namespace daisy::sweep {

// What one run of the pipeline produced.
struct Solution {
    PatchMesh patches;
    WavelengthSet set;
    std::vector<double> radiosity;  // n x m
    Image xyz;  // radiance XYZ per pixel
};

// Fills the error columns of `row` (relativeRmsB, relativeRmsY, errorLevel, meanDeltaE,
// p95DeltaE) from `solution` against `reference`, both images displayed at `exposureScale`.
void measure(const Solution& solution, const Solution& reference, double exposureScale,
             SweepRow& row);

}  // namespace daisy::sweep
