#pragma once
// Wall-clock timing of stages (seconds, steady clock): the one helper every module uses; and the
// process's CPU time.
#include <time.h>

#include <chrono>

namespace daisy {

using Clock = std::chrono::steady_clock;

// Seconds from `start` to now.
inline double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// A stopwatch started at construction.
class Timer {
public:
    Timer() : start_(Clock::now()) {}
    double seconds() const { return secondsSince(start_); }
    void restart() { start_ = Clock::now(); }

private:
    Clock::time_point start_;
};

// CPU seconds the whole process (every thread) has used so far (POSIX CLOCK_PROCESS_CPUTIME_ID).
inline double processCpuSeconds() {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return double(now.tv_sec) + 1e-9 * double(now.tv_nsec);
}

}  // namespace daisy
