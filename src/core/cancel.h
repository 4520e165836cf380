#pragma once
// Cooperative cancellation: long stages (form factors, solves, renders) poll a CancelToken
// between units of work of at most a few milliseconds and stop with a "cancelled" status. The
// viewer cancels a background re-solve with one; SIGINT/SIGTERM cancel the process's token
// (core/interrupt.h).
#include <atomic>

namespace daisy {

class CancelToken {
public:
    void cancel() { flag_.store(true, std::memory_order_relaxed); }
    void reset() { flag_.store(false, std::memory_order_relaxed); }
    bool cancelled() const { return flag_.load(std::memory_order_relaxed); }

private:
    std::atomic<bool> flag_{false};
};

// True when `token` is given and cancelled (a null token never cancels).
inline bool isCancelled(const CancelToken* token) {
    return token && token->cancelled();
}

}  // namespace daisy
