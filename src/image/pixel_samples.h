#pragma once
// Where a pixel's samples lie (DESIGN.md section 7): sample s of a pixel sits in stratum
// (s mod N, (s / N) mod N) of an N x N grid over the pixel, N = ceil(sqrt(samples per pixel)).
// The ray-cast renderers take a fixed place in each stratum (sampleOffset: deterministic,
// noise-free); the path tracer jitters within it. Offsets are in pixels from the pixel's top-left
// corner, in [0, 1).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <array>

namespace daisy {

// N = ceil(sqrt(samplesPerPixel)), at least 1.
inline int samplesPerSide(int samplesPerPixel) {
    int n = 1;
    while (n * n < samplesPerPixel)
        ++n;
    return n;
}

// Offset of sample s in an N x N grid (side = N) with (u, v) in [0, 1) its place inside the
// stratum: (0.5, 0.5) is the stratum's centre.
inline std::array<double, 2> stratumOffset(int s, int side, double u, double v) {
    const int cell = s % (side * side);
    return {((cell % side) + u) / side, ((cell / side) + v) / side};
}

// The ray-cast renderers' sample s: in stratum (i, j) = (s mod N, s / N), at ((j + 1/2) / N,
// (i + 1/2) / N) of the stratum, so the N^2 samples also lie in N^2 distinct columns and N^2
// distinct rows of width 1 / N^2 (multi-jittered sampling, Chiu, Shirley & Wang 1994, in its
// canonical unshuffled arrangement). A horizontal or vertical edge, the common case in a room,
// then covers a pixel by its area fraction rounded to 1 / N^2 instead of 1 / N (stratum centres
// see only N columns). The pattern's mean is the pixel's centre. N = 1: the centre.
inline std::array<double, 2> sampleOffset(int s, int side) {
    const int cell = s % (side * side);
    const int i = cell % side, j = cell / side;
    return stratumOffset(cell, side, (j + 0.5) / side, (i + 0.5) / side);
}

// Runs renderRows(tbb::blocked_range<int>) over the image's rows [0, height) in parallel: in an
// arena of `threads` threads when threads > 0 (RenderSettings::threads), else on all of them.
template <class RowBody>
void forEachImageRow(int height, int threads, const RowBody& renderRows) {
    const tbb::blocked_range<int> allRows(0, height, 1);
    if (threads > 0) {
        tbb::task_arena arena(threads);
        arena.execute([&] { tbb::parallel_for(allRows, renderRows); });
    } else {
        tbb::parallel_for(allRows, renderRows);
    }
}

}  // namespace daisy
