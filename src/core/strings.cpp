#include "core/strings.h"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace daisy {

std::string formatNumber(double value) {
    std::array<char, 64> buffer{};
    const double magnitude = std::fabs(value);
    const bool fixed = magnitude == 0 || (magnitude >= 1e-4 && magnitude < 1e15);
    const auto result = fixed ? std::to_chars(buffer.data(), buffer.data() + buffer.size(), value,
                                              std::chars_format::fixed)
                              : std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    return std::string(buffer.data(), result.ptr);
}

std::string formatNumber(double value, int digits) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
    return buffer;
}

std::string formatCount(uint64_t count) {
    char digits[24];
    const int length =
        std::snprintf(digits, sizeof digits, "%llu", static_cast<unsigned long long>(count));
    char out[32];
    int used = 0;
    for (int i = 0; i < length; ++i) {
        if (i > 0 && (length - i) % 3 == 0) out[used++] = ',';
        out[used++] = digits[i];
    }
    return std::string(out, static_cast<std::size_t>(used));
}

std::string printable(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (byte >= 0x20 && byte != 0x7F) {
            out += c;
            continue;
        }
        switch (c) {
            case '\n':
                out += "\\n";
                break;
            case '\t':
                out += "\\t";
                break;
            case '\r':
                out += "\\r";
                break;
            case '\0':
                out += "\\0";
                break;
            default: {
                const char* digits = "0123456789abcdef";
                out += "\\x";
                out += digits[byte >> 4];
                out += digits[byte & 15];
            }
        }
    }
    return out;
}

std::string toLower(std::string_view text) {
    std::string out(text);
    for (char& c : out)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

std::string formatBytes(double bytes) {
    static const char* const kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    int unit = 0;
    while (bytes >= 1024.0 && unit < 6) {
        bytes /= 1024.0;
        ++unit;
    }
    char buffer[32];
    if (unit == 0) {
        std::snprintf(buffer, sizeof buffer, "%.0f B", bytes);
    } else {
        std::snprintf(buffer, sizeof buffer,
                      bytes < 10        ? "%.2f %s"
                          : bytes < 100 ? "%.1f %s"
                                        : "%.0f %s",
                      bytes, kUnits[unit]);
    }
    return buffer;
}

bool parseByteSize(std::string_view text, std::uint64_t& bytes) {
    std::string s(text);
    const char* begin = s.c_str();
    char* end = nullptr;
    const double number = std::strtod(begin, &end);
    if (end == begin || !std::isfinite(number) || number < 0) return false;
    std::string suffix = toLower(std::string_view(end));
    while (!suffix.empty() && suffix.front() == ' ')
        suffix.erase(suffix.begin());
    double scale = 1;
    if (!suffix.empty()) {
        const char unit = suffix.front();
        const std::string_view rest = std::string_view(suffix).substr(1);
        if (unit == 'b' && rest.empty()) {
            scale = 1;
        } else {
            const std::string_view prefixes = "kmgtp";
            const std::size_t power = prefixes.find(unit);
            if (power == std::string_view::npos) return false;
            if (!(rest.empty() || rest == "b" || rest == "i" || rest == "ib")) return false;
            scale = std::pow(1024.0, static_cast<double>(power + 1));
        }
    }
    const double value = number * scale;
    if (value >= 1.8e19) return false;
    bytes = static_cast<std::uint64_t>(std::llround(value));
    return true;
}

}  // namespace daisy
