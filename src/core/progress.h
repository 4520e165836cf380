#pragma once
// Progress of a long stage on a terminal (DESIGN.md section 9): stage name, percent, rate and
// ETA on one line of stderr, redrawn at most every kRedrawSeconds. Silent when stderr is not a
// terminal or under --quiet, so logs and pipes stay clean. advance() may be called from any
// thread; one of the callers redraws.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace daisy {

// Told of a stage's progress, for front ends that draw their own (the viewer): called from the
// thread that advances the stage, at most every Progress::kRedrawSeconds, and once at its end
// (done == total). Must be cheap and thread-safe.
using ProgressObserver = std::function<void(std::string_view stage, uint64_t done, uint64_t total)>;

class Progress {
public:
    // total: units of work in the stage (> 0 for percentages); unit: their name ("pairs").
    // enabled = false silences the terminal line (tests); by default it follows
    // progressEnabledByDefault(). `observer`, when set, is told either way.
    Progress(std::string stage, uint64_t total, std::string unit);
    Progress(std::string stage, uint64_t total, std::string unit, bool enabled,
             ProgressObserver observer = {});
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    void advance(uint64_t amount);  // thread-safe
    void finish();  // draws the final line and ends it; idempotent, called by the destructor

    uint64_t done() const { return done_.load(std::memory_order_relaxed); }
    double elapsedSeconds() const;

    static constexpr double kRedrawSeconds = 0.2;

private:
    void draw(bool final);

    std::string stage_;
    std::string unit_;
    uint64_t total_;
    bool enabled_;
    ProgressObserver observer_;
    bool finished_ = false;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point start_;
    std::atomic<uint64_t> done_{0};
    std::atomic<int64_t> nextDrawNs_{0};
};

// True when stderr is a terminal and the verbosity is not Quiet.
bool progressEnabledByDefault();

// "3.2 s", "4 min 05 s", "1 h 02 min": a duration for humans.
std::string formatDuration(double seconds);

// "1.23 M", "456 k", "78": a rate or count with an SI prefix, three significant digits.
std::string formatSi(double value);

}  // namespace daisy
