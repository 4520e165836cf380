// libFuzzer target: the option strings the command line hands to the library: the first byte
// picks the parser (--wavelengths through makeWavelengthSet, --max-memory sizes, --exposure,
// --method, --solver, illuminant and fluorophore preset names); the rest is the text.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/strings.h"
#include "image/exposure.h"
#include "radiosity/form_factors.h"
#include "radiosity/solver.h"
#include "spectral/presets.h"
#include "spectral/wavelength_set.h"
#include "spectral/wavelength_spec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
    switch (data[0] % 6) {
        case 0: {
            auto spec = daisy::parseWavelengthSpec(text);
            if (spec) {
                for (int flags = 0; flags < 4; ++flags) {
                    auto set = daisy::makeWavelengthSet(*spec, flags & 1, flags & 2);
                    if (set && set->size() > 0) (void)set->wavelengthNm(set->size() - 1);
                }
            }
            break;
        }
        case 1: {
            uint64_t bytes = 0;
            (void)daisy::parseByteSize(text, bytes);
            break;
        }
        case 2:
            (void)daisy::parseExposure(text);
            break;
        case 3: {
            daisy::FormFactorMethod method;
            daisy::SolverKind kind;
            (void)daisy::parseFormFactorMethod(text, method);
            (void)daisy::parseSolverKind(text, kind);
            break;
        }
        case 4:
            (void)daisy::canonicalIlluminantPreset(text);
            break;
        default:
            (void)daisy::canonicalFluorophorePreset(text);
            break;
    }
    return 0;
}
