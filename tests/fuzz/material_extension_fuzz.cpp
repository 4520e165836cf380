// libFuzzer target: any bytes as the JSON of one DAISY_materials_spectral object, through the
// bounded JSON parser (scene/bounded_json.h) and parseMaterialExtension: a MaterialExtension or
// an Error, never a crash.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "scene/bounded_json.h"
#include "scene/material_extension.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto json = daisy::parseBoundedJson(text);
    if (!json) return 0;
    (void)daisy::parseMaterialExtension(*json, "materials[0].extensions.DAISY_materials_spectral");
    return 0;
}
