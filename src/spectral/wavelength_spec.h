#pragma once
// The --wavelengths option as written (DESIGN.md section 4): a preset name, "A:B:STEP" or a
// comma-separated list, in nm. Parsed and checked here; the sampled WavelengthSet is built from
// it by the spectral module.
#include <string>
#include <string_view>
#include <vector>

#include "core/expected.h"

namespace daisy {

struct WavelengthSpec {
    enum class Kind { Preset, Range, List };
    Kind kind = Kind::Preset;
    std::string preset = "auto";  // daisyriot | meyer4 | visible | fine | auto
    double startNm = 0, endNm = 0;  // Range: start..end inclusive
    double stepNm = 0;  // Range: > 0
    std::vector<double> listNm;  // List: strictly ascending
};

// Wavelengths accepted anywhere in the program: [kMinWavelengthNm, kMaxWavelengthNm].
inline constexpr double kMinWavelengthNm = 200.0;
inline constexpr double kMaxWavelengthNm = 2500.0;

Expected<WavelengthSpec> parseWavelengthSpec(std::string_view text);

}  // namespace daisy
