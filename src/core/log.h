#pragma once
// Diagnostics on stderr, filtered by a process-wide verbosity (--quiet / --verbose).
// Results that a command prints (e.g. `daisy info`) go to stdout, not through here.
#include <string>

namespace daisy {

enum class Verbosity { Quiet, Normal, Verbose };

void setVerbosity(Verbosity verbosity);
Verbosity verbosity();

void logWarning(const std::string& message);  // "warning: ...", hidden by --quiet
void logInfo(const std::string& message);  // hidden by --quiet
void logVerbose(const std::string& message);  // shown only with --verbose
void logError(const std::string& message);  // "error: ...", always shown

}  // namespace daisy
