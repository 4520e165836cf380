#pragma once
// The command line's common options as the library's session settings (pipeline/session.h).
#include "app/options.h"
#include "pipeline/session.h"

namespace daisy::app {

// Everything the session takes from the options; `defaultSize` is what the patch size is when
// --subdivide is not given. The disk cache is --cache DIR, else the default folder
// (FormFactorCache::defaultDirectory), and none with --no-cache.
SessionSettings sessionSettingsFrom(const CommonOptions& options, PatchSizeDefault defaultSize);

// Opens a session on the options' scene and prints the message of an error (exit status 2).
Expected<Session> openSession(const CommonOptions& options, PatchSizeDefault defaultSize,
                              const std::function<Expected<void>(const Scene&)>& afterLoad = {});

// Prints the error of a stage that SIGINT / SIGTERM can stop (the interrupt token's). When a
// signal stopped it, the stage's own "interrupted" error may arrive before the signal watchdog
// has printed its line: then that line and exit status 130 instead (core/interrupt.h), as
// main() does for the errors that reach it.
void logStageError(const Error& error);

// A solve that SIGINT / SIGTERM cancel (core/interrupt.h) and that takes a converged solution
// from the disk cache when it holds one (pipeline/solution_cache.h).
SolveRequest interruptibleSolve();

// F (memory, the disk cache or the backend), then an interruptible solve, as render and view
// run them. Prints the message of an error and returns false (exit status 2). `report`, when
// given, receives how F was made.
bool buildAndSolve(Session& session, FormFactorReport* report = nullptr);

}  // namespace daisy::app
