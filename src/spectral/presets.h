#pragma once
// The names of built-in spectra. Matching is case-insensitive; the canonical spelling is returned.
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace daisy {

// Illuminants: "D65", "D50", "A", "F1".."F12" (CIE 015:2018) and "blacklight" (UV-A lamp).
std::span<const std::string_view> illuminantPresetNames();
std::optional<std::string> canonicalIlluminantPreset(std::string_view name);

// Fluorophores: "brightener" (optical brightener), "fluorescein", "rhodamine6g", "neon".
std::span<const std::string_view> fluorophorePresetNames();
std::optional<std::string> canonicalFluorophorePreset(std::string_view name);

// "a, b, c" for messages that list the valid choices.
std::string joinNames(std::span<const std::string_view> names);

}  // namespace daisy
