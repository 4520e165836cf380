#include "core/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>

#include "core/log.h"

namespace daisy {
namespace {

int64_t nanoseconds(std::chrono::steady_clock::duration d) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(d).count();
}

}  // namespace

bool progressEnabledByDefault() {
    return verbosity() != Verbosity::Quiet && isatty(fileno(stderr)) == 1;
}

Progress::Progress(std::string stage, uint64_t total, std::string unit)
    : Progress(std::move(stage), total, std::move(unit), progressEnabledByDefault()) {}

Progress::Progress(std::string stage, uint64_t total, std::string unit, bool enabled,
                   ProgressObserver observer)
    : stage_(std::move(stage)),
      unit_(std::move(unit)),
      total_(total),
      enabled_(enabled),
      observer_(std::move(observer)),
      start_(std::chrono::steady_clock::now()) {
    nextDrawNs_ = static_cast<int64_t>(kRedrawSeconds * 1e9);
}

Progress::~Progress() {
    finish();
}

double Progress::elapsedSeconds() const {
    return 1e-9 * static_cast<double>(nanoseconds(std::chrono::steady_clock::now() - start_));
}

void Progress::advance(uint64_t amount) {
    done_.fetch_add(amount, std::memory_order_relaxed);
    if (!enabled_ && !observer_) return;
    const int64_t now = nanoseconds(std::chrono::steady_clock::now() - start_);
    int64_t next = nextDrawNs_.load(std::memory_order_relaxed);
    // The thread that moves the deadline forward draws; the others carry on.
    if (now >= next &&
        nextDrawNs_.compare_exchange_strong(next,
                                            now + static_cast<int64_t>(kRedrawSeconds * 1e9))) {
        if (observer_) observer_(stage_, done_.load(std::memory_order_relaxed), total_);
        if (enabled_) draw(false);
    }
}

void Progress::finish() {
    if (finished_) return;
    finished_ = true;
    if (observer_) observer_(stage_, total_, total_);
    if (enabled_ && drawn_) draw(true);
}

void Progress::draw(bool final) {
    const double seconds = elapsedSeconds();
    const uint64_t done = done_.load(std::memory_order_relaxed);
    const double fraction = total_ > 0 ? std::min(1.0, double(done) / double(total_)) : 0.0;
    const double rate = seconds > 0 ? double(done) / seconds : 0.0;
    std::string eta;
    if (final) {
        eta = "in " + formatDuration(seconds);
    } else if (rate > 0 && total_ > done) {
        eta = "ETA " + formatDuration(double(total_ - done) / rate);
    }
    std::fprintf(stderr, "\r%s %5.1f%%  %s%s/s  %s\033[K%s", stage_.c_str(), 100.0 * fraction,
                 formatSi(rate).c_str(), unit_.c_str(), eta.c_str(), final ? "\n" : "");
    std::fflush(stderr);
    drawn_ = true;
}

std::string formatDuration(double seconds) {
    char buffer[48];
    if (!(seconds >= 0) || !std::isfinite(seconds)) return "?";
    if (seconds < 60) {
        std::snprintf(buffer, sizeof buffer, seconds < 10 ? "%.1f s" : "%.0f s", seconds);
    } else if (seconds < 3600) {
        const auto s = static_cast<long long>(seconds + 0.5);
        std::snprintf(buffer, sizeof buffer, "%lld min %02lld s", s / 60, s % 60);
    } else {
        const auto m = static_cast<long long>(seconds / 60 + 0.5);
        std::snprintf(buffer, sizeof buffer, "%lld h %02lld min", m / 60, m % 60);
    }
    return buffer;
}

std::string formatSi(double value) {
    static const char* const kPrefixes[] = {"", " k", " M", " G", " T"};
    int prefix = 0;
    while (std::fabs(value) >= 1000 && prefix < 4) {
        value /= 1000;
        ++prefix;
    }
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.3g%s ", value, kPrefixes[prefix]);
    return buffer;
}

}  // namespace daisy
