#pragma once
// DAISY_CHECK: always-on checks for programmer bugs (never for bad input, which returns
// Expected). On failure prints the condition, its place and optional values, then aborts.
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace daisy::detail {

[[noreturn]] inline void checkFailed(const char* condition, const char* file, int line,
                                     const std::string& values) {
    std::fprintf(stderr, "daisy: internal check failed: %s at %s:%d%s%s\n", condition, file, line,
                 values.empty() ? "" : " with ", values.c_str());
    std::fflush(stderr);
    std::abort();
}

}  // namespace daisy::detail

#define DAISY_CHECK(condition)                                                \
    do {                                                                      \
        if (!(condition)) {                                                   \
            ::daisy::detail::checkFailed(#condition, __FILE__, __LINE__, ""); \
        }                                                                     \
    } while (0)

// DAISY_CHECK_OP(a, <, b) prints both operands when the comparison fails.
#define DAISY_CHECK_OP(a, op, b)                                                         \
    do {                                                                                 \
        const auto& daisyCheckA_ = (a);                                                  \
        const auto& daisyCheckB_ = (b);                                                  \
        if (!(daisyCheckA_ op daisyCheckB_)) {                                           \
            std::ostringstream daisyCheckOut_;                                           \
            daisyCheckOut_ << #a " = " << daisyCheckA_ << ", " #b " = " << daisyCheckB_; \
            ::daisy::detail::checkFailed(#a " " #op " " #b, __FILE__, __LINE__,          \
                                         daisyCheckOut_.str());                          \
        }                                                                                \
    } while (0)
