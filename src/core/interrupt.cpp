#include "core/interrupt.h"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <mutex>
#include <set>
#include <thread>

namespace daisy {
namespace {

std::atomic<int> gSignal{0};
int gWakePipe[2] = {-1, -1};  // the handler writes one byte; the watchdog reads it

// The registry of temporary files. Leaked on purpose: the watchdog may use it while static
// destructors run at exit.
struct TempFiles {
    std::mutex mutex;
    std::set<std::string> paths;
};
TempFiles& tempFiles() {
    static TempFiles* files = new TempFiles;
    return *files;
}

void onSignal(int signal) {
    int expected = 0;
    gSignal.compare_exchange_strong(expected, signal);
    interruptToken().cancel();  // a lock-free atomic store: async-signal-safe
    const char byte = 1;
    if (gWakePipe[1] >= 0) (void)!write(gWakePipe[1], &byte, 1);
}

// Holds the registry's lock until the process ends, so no temporary appears after cleanup.
[[noreturn]] void cleanUpAndExit() {
    TempFiles& files = tempFiles();
    files.mutex.lock();
    for (const std::string& path : files.paths)
        std::remove(path.c_str());
    const int signal = gSignal.load();
    std::fprintf(stderr, "error: interrupted by %s; stopped, temporary files removed\n",
                 signal == SIGTERM ? "SIGTERM" : "SIGINT");
    std::fflush(stderr);
    _exit(kInterruptedExitStatus);
}

void watchdog(double graceSeconds) {
    char byte = 0;
    while (read(gWakePipe[0], &byte, 1) != 1) {
    }
    if (graceSeconds > 0) {
        pollfd none{-1, 0, 0};
        poll(&none, 0, static_cast<int>(graceSeconds * 1000));
    }
    cleanUpAndExit();
}

}  // namespace

CancelToken& interruptToken() {
    static CancelToken token;
    return token;
}

void installInterruptHandlers(double graceSeconds) {
    static std::once_flag once;
    std::call_once(once, [graceSeconds] {
        if (pipe(gWakePipe) != 0) return;
        fcntl(gWakePipe[1], F_SETFL, O_NONBLOCK);
        std::thread(watchdog, graceSeconds).detach();
        struct sigaction action {};
        action.sa_handler = onSignal;
        sigemptyset(&action.sa_mask);
        sigaction(SIGINT, &action, nullptr);
        sigaction(SIGTERM, &action, nullptr);
    });
}

void registerTempFile(const std::string& path) {
    TempFiles& files = tempFiles();
    std::lock_guard lock(files.mutex);
    files.paths.insert(path);
}

void unregisterTempFile(const std::string& path) {
    TempFiles& files = tempFiles();
    std::lock_guard lock(files.mutex);
    files.paths.erase(path);
}

void exitInterrupted() {
    cleanUpAndExit();
}

int interruptSignal() {
    return gSignal.load();
}

}  // namespace daisy
