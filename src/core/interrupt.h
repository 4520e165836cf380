#pragma once
// SIGINT / SIGTERM for the command line and any front end that wants them: the
// handler cancels the process-wide interruptToken() (long stages poll it, core/cancel.h) and
// wakes a watchdog thread, which removes every registered temporary file (atomic_file.h
// registers its temporaries here, a cache registers its partial entries), prints one line to
// stderr and ends the process with exit status 130 (128 + SIGINT, the shell's convention) within
// `graceSeconds` of the signal. The grace lets a front end that polls the token stop by itself:
// it calls exitInterrupted() once its stage has returned.
#include <string>

#include "core/cancel.h"

namespace daisy {

inline constexpr int kInterruptedExitStatus = 130;

// The token SIGINT / SIGTERM cancel once the handlers are installed.
CancelToken& interruptToken();

// Installs the handlers and starts the watchdog (idempotent). graceSeconds = 0: exit at once.
void installInterruptHandlers(double graceSeconds = 0);

// Registers a file to delete when the process is interrupted, until unregisterTempFile. Blocks
// once an interrupt is being handled, so no file is created after the cleanup has run.
void registerTempFile(const std::string& path);
void unregisterTempFile(const std::string& path);

// Removes the registered files, prints "error: interrupted by SIGINT; stopped, temporary files
// removed" (or SIGTERM) and exits with 130.
// For a front end that saw interruptToken() cancelled after a stage returned.
[[noreturn]] void exitInterrupted();

// The signal that cancelled interruptToken() (SIGINT or SIGTERM), 0 when none.
int interruptSignal();

}  // namespace daisy
