#pragma once
// The subcommands behind `daisy`. Each returns the process exit status: 0 done, 2 bad usage or
// bad input (message already printed), 1 any other failure.
#include "app/options.h"

namespace daisy::app {

int runInfo(const CommonOptions& options);

// `daisy formfactors SCENE -o F.mtx [--patches-out patches.csv]`.
int runFormFactors(const CommonOptions& options, const ExportOptions& exports);

// `daisy solve SCENE [--patches-out patches.csv]`: spectral radiosity with fluorescence.
int runSolve(const CommonOptions& options, const ExportOptions& exports);

// `daisy render SCENE -o out.png|.exr|.pfm`: the whole pipeline, then a ray-cast image (issue 6).
int runRender(const CommonOptions& options, const RenderOptions& render);

// `daisy view SCENE [--screenshot out.png --frames N]`: the viewer (issue 15, docs/viewer.md).
int runView(const CommonOptions& options, const ViewOptions& view);

// `daisy validate SCENE --backend vulkan|cuda --against reference`: entry-by-entry comparison
// of two backends' matrices; 1 when over tolerance.
int runValidate(const CommonOptions& options, const ValidateOptions& validate);

// `daisy bench [SCENE] [--stress] [--quick] [-o results.csv]` (issue 7).
int runBench(const CommonOptions& options, const BenchOptions& bench);

// `daisy cache list|clear|prune [--cache DIR] [--cache-size N]` (docs/cache.md): adds the
// subcommand with its options bound to `options`; runCache runs it.
CLI::App* addCacheCommand(CLI::App& app, CacheOptions& options);
int runCache(const CacheOptions& options);

// For subcommands whose stage has not landed: says so on stderr and returns 2.
int notBuiltYet(const char* command, const char* stage);

}  // namespace daisy::app
