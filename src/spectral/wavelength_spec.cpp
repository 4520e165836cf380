#include "spectral/wavelength_spec.h"

#include <cmath>
#include <cstdlib>

#include "core/strings.h"

namespace daisy {
namespace {

bool parseNumber(std::string_view text, double& value) {
    const std::string s(text);
    if (s.empty()) return false;
    char* end = nullptr;
    value = std::strtod(s.c_str(), &end);
    while (end && *end == ' ')
        ++end;
    return end && *end == '\0' && std::isfinite(value);
}

Expected<void> checkRange(double nm, std::string_view text) {
    if (nm < kMinWavelengthNm || nm > kMaxWavelengthNm) {
        return Error{concat("wavelength ", nm, " nm in '", text, "' is outside [", kMinWavelengthNm,
                            ", ", kMaxWavelengthNm, "] nm")};
    }
    return {};
}

}  // namespace

Expected<WavelengthSpec> parseWavelengthSpec(std::string_view text) {
    WavelengthSpec spec;
    const std::string lowered = toLower(text);
    for (const char* preset : {"daisyriot", "meyer4", "visible", "fine", "auto"}) {
        if (lowered == preset) {
            spec.preset = preset;
            return spec;
        }
    }
    if (text.find(':') != std::string_view::npos) {
        const std::size_t first = text.find(':');
        const std::size_t second = text.find(':', first + 1);
        double start, end, step;
        if (second == std::string_view::npos ||
            text.find(':', second + 1) != std::string_view::npos ||
            !parseNumber(text.substr(0, first), start) ||
            !parseNumber(text.substr(first + 1, second - first - 1), end) ||
            !parseNumber(text.substr(second + 1), step)) {
            return Error{concat("'", text, "' is not A:B:STEP (numbers in nm)")};
        }
        if (!(step > 0) || !(end >= start)) {
            return Error{concat("'", text, "' needs A <= B and STEP > 0")};
        }
        if (auto ok = checkRange(start, text); !ok) return ok.error();
        if (auto ok = checkRange(end, text); !ok) return ok.error();
        if ((end - start) / step > 10000) {
            return Error{concat("'", text, "' has more than 10000 samples")};
        }
        spec.kind = WavelengthSpec::Kind::Range;
        spec.startNm = start;
        spec.endNm = end;
        spec.stepNm = step;
        return spec;
    }
    spec.kind = WavelengthSpec::Kind::List;
    std::size_t begin = 0;
    while (begin <= text.size()) {
        std::size_t comma = text.find(',', begin);
        if (comma == std::string_view::npos) comma = text.size();
        double nm;
        if (!parseNumber(text.substr(begin, comma - begin), nm)) {
            return Error{concat("'", text,
                                "' is not a wavelength set: use daisyriot, meyer4, visible, fine, "
                                "auto, A:B:STEP or a comma-separated list in nm")};
        }
        if (auto ok = checkRange(nm, text); !ok) return ok.error();
        if (!spec.listNm.empty() && nm <= spec.listNm.back()) {
            return Error{concat("wavelengths in '", text, "' must be strictly ascending")};
        }
        spec.listNm.push_back(nm);
        begin = comma + 1;
    }
    return spec;
}

}  // namespace daisy
