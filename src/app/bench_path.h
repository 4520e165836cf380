#pragma once
// `daisy bench SCENE --reference path` (issue 16): the radiosity image's error and run time
// against the independent path tracer's converged image, next to the path tracer's own
// error-time curve (bench_path.cpp describes the rows and files).
#include "app/options.h"

namespace daisy::app {

int runPathBench(const CommonOptions& options, const BenchOptions& bench);

}  // namespace daisy::app
