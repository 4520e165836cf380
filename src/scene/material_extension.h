#pragma once
// Parses a DAISY_materials_spectral object (DESIGN.md section 10) into typed data, checking
// every value. `where` is the JSON path of `object` (e.g. "materials[2].extensions.
// DAISY_materials_spectral"); error messages extend it to the offending member, e.g.
// "<where>.reflectance.values[3]: 1.2 is outside [0, 1]". The caller prefixes the file name.
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "core/expected.h"
#include "scene/material.h"

namespace daisy {

inline constexpr const char* kSpectralExtensionName = "DAISY_materials_spectral";

Expected<MaterialExtension> parseMaterialExtension(const nlohmann::json& object,
                                                   const std::string& where);

// The inverse of parseMaterialExtension: the DAISY_materials_spectral object (or --materials
// entry) that parses back to `extension` exactly (numbers written to round-trip), with only the
// members it sets ("fluorescence": null when it removes fluorescence). MTL's fluorescent colour
// (Ks) has no JSON form: `fluorescence` is left out for it and `representable` set to false.
nlohmann::json materialExtensionToJson(const MaterialExtension& extension,
                                       bool* representable = nullptr);

}  // namespace daisy
