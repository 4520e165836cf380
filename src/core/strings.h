#pragma once
// Small string helpers used in messages and option parsing.
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>

namespace daisy {

// concat("a", 1, 'b') -> "a1b", through an ostringstream (17 significant digits for doubles).
template <typename... Args>
std::string concat(const Args&... args) {
    std::ostringstream out;
    out.precision(17);
    (out << ... << args);
    return out.str();
}

std::string toLower(std::string_view text);

// "1.5 GiB", "12 KiB", "800 B": binary units, three significant digits.
std::string formatBytes(double bytes);

// Parses "1000", "512M", "2G", "1.5GiB", "64 MiB", "3GB" (binary multiples for K/M/G/T, with or
// without "i"/"B"). Returns false for anything else, negative or non-finite values.
bool parseByteSize(std::string_view text, std::uint64_t& bytes);

}  // namespace daisy
