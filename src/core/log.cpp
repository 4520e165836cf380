#include "core/log.h"

#include <atomic>
#include <cstdio>

#include "core/strings.h"

namespace daisy {
namespace {

std::atomic<Verbosity> gVerbosity{Verbosity::Normal};

void print(const char* prefix, const std::string& message) {
    std::fprintf(stderr, "%s%s\n", prefix, message.c_str());
}

// Errors and warnings are one line each, whatever names from files they quote.
void printOneLine(const char* prefix, const std::string& message) {
    print(prefix, printable(message));
}

}  // namespace

void setVerbosity(Verbosity value) {
    gVerbosity = value;
}
Verbosity verbosity() {
    return gVerbosity;
}

void logWarning(const std::string& message) {
    if (gVerbosity != Verbosity::Quiet) printOneLine("warning: ", message);
}

void logInfo(const std::string& message) {
    if (gVerbosity != Verbosity::Quiet) print("", message);
}

void logVerbose(const std::string& message) {
    if (gVerbosity == Verbosity::Verbose) print("", message);
}

void logError(const std::string& message) {
    printOneLine("error: ", message);
}

}  // namespace daisy
