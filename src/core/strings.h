#pragma once
// Small string helpers used in messages and option parsing.
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>

namespace daisy {

// The shortest text that reads back as the same double: "1.2", not "1.1999999999999999", and
// "200000", not "2e+05" (fixed notation unless the magnitude is extreme).
std::string formatNumber(double value);

// `value` rounded to `digits` significant digits, "%g" style: formatNumber(1.93434568, 4) =
// "1.934".
std::string formatNumber(double value, int digits);

// A count with thousands separators: 478306937 -> "478,306,937".
std::string formatCount(uint64_t count);

// concat("a", 1, 'b', 0.1) -> "a1b0.1", through an ostringstream; floating-point arguments are
// written with formatNumber.
template <typename... Args>
std::string concat(const Args&... args) {
    std::ostringstream out;
    const auto append = [&out](const auto& arg) {
        if constexpr (std::is_floating_point_v<std::decay_t<decltype(arg)>>) {
            out << formatNumber(static_cast<double>(arg));
        } else {
            out << arg;
        }
    };
    (append(args), ...);
    return out.str();
}

std::string toLower(std::string_view text);

// `text` with every control character (below 0x20, and 0x7F) written as a C escape ("\n", "\t",
// "\r", "\0", "\x1b") and backslashes left as they are, so a name from a file prints on one
// line and whole: a newline cannot start a forged "error:" line, a NUL cannot cut the message.
std::string printable(std::string_view text);

// "1.5 GiB", "12 KiB", "800 B": binary units, three significant digits.
std::string formatBytes(double bytes);

// Parses "1000", "512M", "2G", "1.5GiB", "64 MiB", "3GB" (binary multiples for K/M/G/T, with or
// without "i"/"B"). Returns false for anything else, negative or non-finite values.
bool parseByteSize(std::string_view text, std::uint64_t& bytes);

}  // namespace daisy
