#include "scene/obj_syntax.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "core/strings.h"

namespace daisy {
namespace {

// Splits `text` into lines (\n, \r\n or \r) and calls visit(lineNumber, keyword, arguments).
template <typename Visit>
Expected<void> forEachStatement(std::string_view text, Visit&& visit) {
    std::size_t lineNumber = 0, start = 0;
    while (start < text.size()) {
        std::size_t end = text.find_first_of("\r\n", start);
        if (end == std::string_view::npos) end = text.size();
        ++lineNumber;
        std::string_view line = text.substr(start, end - start);
        start = end + 1;
        if (end < text.size() && text[end] == '\r' && start < text.size() && text[start] == '\n') {
            ++start;
        }
        if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) {
            line = line.substr(0, hash);
        }
        std::vector<std::string_view> words;
        std::size_t at = 0;
        while (at < line.size()) {
            const std::size_t begin = line.find_first_not_of(" \t\v\f", at);
            if (begin == std::string_view::npos) break;
            std::size_t stop = line.find_first_of(" \t\v\f", begin);
            if (stop == std::string_view::npos) stop = line.size();
            words.push_back(line.substr(begin, stop - begin));
            at = stop;
        }
        if (words.empty()) continue;
        auto ok = visit(lineNumber, words[0],
                        std::vector<std::string_view>(words.begin() + 1, words.end()));
        if (!ok) return ok;
    }
    return {};
}

bool isFiniteNumber(std::string_view word) {
    const std::string text(word);
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || text.empty()) return false;
    // strtod accepts "nan", "inf" and hex floats; OBJ writers emit none of them.
    for (char c : text) {
        if (c == 'n' || c == 'N' || c == 'x' || c == 'X') return false;
    }
    return std::isfinite(value);
}

bool isNonZeroInteger(std::string_view word) {
    if (word.starts_with('-') || word.starts_with('+')) word.remove_prefix(1);
    if (word.empty() || word.size() > 10) return false;
    bool nonZero = false;
    for (char c : word) {
        if (c < '0' || c > '9') return false;
        nonZero = nonZero || c != '0';
    }
    return nonZero;
}

// v, v/t, v//n or v/t/n with non-zero integers.
bool isCornerReference(std::string_view word) {
    std::size_t part = 0, start = 0;
    while (true) {
        const std::size_t slash = word.find('/', start);
        const std::string_view piece = word.substr(start, slash - start);
        const bool optional = part > 0;  // the texture index may be empty (v//n)
        if (!(piece.empty() && optional && slash != std::string_view::npos) &&
            !isNonZeroInteger(piece)) {
            return false;
        }
        if (slash == std::string_view::npos) return true;
        if (++part > 2) return false;
        start = slash + 1;
    }
}

Error badNumber(const std::string& file, std::size_t line, std::string_view keyword,
                std::string_view word, const char* expected) {
    return Error{concat(file, ":", line, ": ", keyword, ": '", word,
                        "' is not a finite number (expected ", expected, ")")};
}

Expected<void> checkCount(const std::string& file, std::size_t line, std::string_view keyword,
                          std::size_t count, std::size_t low, std::size_t high,
                          const char* expected) {
    if (count < low || count > high) {
        return Error{concat(file, ":", line, ": ", keyword, ": ", count, " numbers (expected ",
                            expected, ")")};
    }
    return {};
}

}  // namespace

Expected<void> checkObjNumbers(std::string_view text, const std::string& file) {
    return forEachStatement(
        text,
        [&](std::size_t line, std::string_view keyword,
            const std::vector<std::string_view>& args) -> Expected<void> {
            const char* expected = keyword == "v" ? "x y z [w]"
                : keyword == "vn"                 ? "x y z"
                : keyword == "vt"                 ? "u [v [w]]"
                                                  : nullptr;
            if (expected != nullptr) {
                for (std::string_view word : args) {
                    if (!isFiniteNumber(word))
                        return badNumber(file, line, keyword, word, expected);
                }
                // "v x y z r g b" (vertex colours) has 6 or 7 numbers.
                const std::size_t low = keyword == "vt" ? 1 : 3;
                const std::size_t high = keyword == "v" ? 7 : keyword == "vt" ? 3 : 3;
                return checkCount(file, line, keyword, args.size(), low, high, expected);
            }
            if (keyword == "f" || keyword == "l" || keyword == "p") {
                for (std::string_view word : args) {
                    if (!isCornerReference(word)) {
                        return Error{
                            concat(file, ":", line, ": ", keyword, ": '", word,
                                   "' is not a vertex reference (expected v, v/vt, v//vn or "
                                   "v/vt/vn with non-zero integers)")};
                    }
                }
                if (keyword == "f" && args.size() < 3) {
                    return Error{concat(file, ":", line, ": f: ", args.size(),
                                        " corners (a face needs at least 3)")};
                }
            }
            return {};
        });
}

Expected<void> checkMtlNumbers(std::string_view text, const std::string& file) {
    return forEachStatement(
        text,
        [&](std::size_t line, std::string_view keyword,
            const std::vector<std::string_view>& args) -> Expected<void> {
            const bool colour = keyword == "Ka" || keyword == "Kd" || keyword == "Ks" ||
                keyword == "Ke" || keyword == "Tf";
            const bool scalar =
                keyword == "Ns" || keyword == "Ni" || keyword == "d" || keyword == "Tr";
            if (colour) {
                if (!args.empty() && (args[0] == "spectral" || args[0] == "xyz")) return {};
                for (std::string_view word : args) {
                    if (!isFiniteNumber(word)) return badNumber(file, line, keyword, word, "r g b");
                }
                if (args.size() != 1 && args.size() != 3) {
                    return checkCount(file, line, keyword, args.size(), 3, 3, "r g b");
                }
            } else if (scalar) {
                // "d -halo 0.5" is an MTL option form.
                const std::size_t first = !args.empty() && args[0] == "-halo" ? 1 : 0;
                for (std::size_t i = first; i < args.size(); ++i) {
                    if (!isFiniteNumber(args[i])) {
                        return badNumber(file, line, keyword, args[i], "one number");
                    }
                }
                return checkCount(file, line, keyword, args.size() - first, 1, 1, "one number");
            }
            return {};
        });
}

std::vector<std::string> objMaterialLibraries(std::string_view text) {
    std::vector<std::string> names;
    (void)forEachStatement(text,
                           [&](std::size_t, std::string_view keyword,
                               const std::vector<std::string_view>& args) -> Expected<void> {
                               if (keyword == "mtllib") {
                                   for (std::string_view word : args)
                                       names.emplace_back(word);
                               }
                               return {};
                           });
    return names;
}

}  // namespace daisy
