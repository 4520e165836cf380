#pragma once
// `daisy bench SCENE`: run time against error (issue 7). Sweeps the settings that trade time for
// accuracy one at a time around the current settings (the command line's, i.e. the defaults
// unless overridden): method, quadrature L, rays K, subdivision (patch budgets), wavelength set,
// solver tolerance and backend. Every row runs the whole pipeline from the scene's triangles
// (patches, F, radiosity system and solve, shading and a ray-cast image), timing each stage and
// taking the peak resident memory of the row (core/memory.h), and measures its error against
// the reference:
// - the analytic answer when the scene is a furnace (closed, one non-fluorescent reflectance,
//   the same emission everywhere: B = E / (1 - rho) exactly), else
// - a converged high-setting solution of the same scene (hybrid L=2, K=64, the fine wavelength
//   set with UV excitation samples, tolerance 1e-6, twice the default row's patches), computed
//   once and cached on disk beside the CSV (keyed by the scene file's bytes and those settings).
// Errors: area-weighted relative RMS of B over patches and wavelength samples (the reference
// spectrum interpolated to the row's samples) and of the luminance Y; patch by patch when the
// row's patches are the reference's, else per source triangle (area-weighted means); and the
// image's mean and 95th-percentile CIEDE2000 against the reference render (same camera and
// exposure, 8-bit sRGB as displayed). Output: a CSV, a log-log plot of image error against
// time with the Pareto front and the just-noticeable difference marked, the reference image,
// and on the terminal the table and the cheapest setting under the JND.
#include "app/options.h"

namespace daisy::app {

// Image error a person just notices: mean CIEDE2000 of 1 (Sharma et al. 2005 state Delta E00
// ~ 1 as the threshold of a just-perceptible difference for side-by-side patches).
inline constexpr double kJustNoticeableDeltaE = 1.0;

int runSweep(const CommonOptions& options, const BenchOptions& bench);

}  // namespace daisy::app
