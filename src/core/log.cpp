#include "core/log.h"

#include <atomic>
#include <cstdio>

namespace daisy {
namespace {

std::atomic<Verbosity> gVerbosity{Verbosity::Normal};

void print(const char* prefix, const std::string& message) {
    std::fprintf(stderr, "%s%s\n", prefix, message.c_str());
}

}  // namespace

void setVerbosity(Verbosity value) {
    gVerbosity = value;
}
Verbosity verbosity() {
    return gVerbosity;
}

void logWarning(const std::string& message) {
    if (gVerbosity != Verbosity::Quiet) print("warning: ", message);
}

void logInfo(const std::string& message) {
    if (gVerbosity != Verbosity::Quiet) print("", message);
}

void logVerbose(const std::string& message) {
    if (gVerbosity == Verbosity::Verbose) print("", message);
}

void logError(const std::string& message) {
    print("error: ", message);
}

}  // namespace daisy
