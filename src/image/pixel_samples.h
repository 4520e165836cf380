#pragma once
// Where a pixel's samples lie (DESIGN.md section 7): sample s of a pixel sits in stratum
// (s mod N, (s / N) mod N) of an N x N grid over the pixel, N = ceil(sqrt(samples per pixel)).
// The ray-cast renderer takes each stratum's centre (deterministic, noise-free); the path tracer
// jitters within it. Offsets are in pixels from the pixel's top-left corner, in [0, 1).
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
inline std::array<double, 2> stratumOffset(int s, int side, double u = 0.5, double v = 0.5) {
    const int cell = s % (side * side);
    return {((cell % side) + u) / side, ((cell / side) + v) / side};
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
