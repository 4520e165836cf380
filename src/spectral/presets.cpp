#include "spectral/presets.h"

#include <array>

#include "core/strings.h"

namespace daisy {
namespace {

constexpr std::array<std::string_view, 16> kIlluminants = {
    "D65", "D50", "A",  "F1", "F2",  "F3",  "F4",  "F5",
    "F6",  "F7",  "F8", "F9", "F10", "F11", "F12", "blacklight"};

constexpr std::array<std::string_view, 4> kFluorophores = {"brightener", "fluorescein",
                                                           "rhodamine6g", "neon"};

std::optional<std::string> findCanonical(std::span<const std::string_view> names,
                                         std::string_view name) {
    const std::string lowered = toLower(name);
    for (std::string_view candidate : names) {
        if (toLower(candidate) == lowered) return std::string(candidate);
    }
    return std::nullopt;
}

}  // namespace

std::span<const std::string_view> illuminantPresetNames() {
    return kIlluminants;
}
std::span<const std::string_view> fluorophorePresetNames() {
    return kFluorophores;
}

std::optional<std::string> canonicalIlluminantPreset(std::string_view name) {
    return findCanonical(kIlluminants, name);
}

std::optional<std::string> canonicalFluorophorePreset(std::string_view name) {
    return findCanonical(kFluorophores, name);
}

std::string joinNames(std::span<const std::string_view> names) {
    std::string out;
    for (std::string_view name : names) {
        if (!out.empty()) out += ", ";
        out += name;
    }
    return out;
}

}  // namespace daisy
