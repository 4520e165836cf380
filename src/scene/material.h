#pragma once
// A surface material as loaded: RGB values from the core format (glTF baseColorFactor and
// emissiveFactor x KHR_materials_emissive_strength, or MTL Kd/Ke) plus, where given, the spectral
// description of the DAISY_materials_spectral extension, which takes precedence.
#include <array>
#include <optional>
#include <string>

#include "scene/texture.h"
#include "spectral/spectrum_spec.h"

namespace daisy {

// The spectral part of a material: the DAISY_materials_spectral extension object, or an entry
// of a --materials JSON file. Absent members leave the material's RGB-derived values in force.
struct MaterialExtension {
    std::optional<SpectrumSpec> reflectance;
    std::optional<SpectrumSpec> emission;
    std::optional<FluorescenceSpec> fluorescence;
    // "fluorescence": null in an overlay (a --materials entry): the material loses its
    // fluorescence. Set only when `fluorescence` is empty.
    bool removesFluorescence = false;
};

struct Material {
    std::string name;
    std::string origin;  // "scene.gltf: materials[2]", for messages
    std::array<double, 3> baseColor{0.8, 0.8, 0.8};  // linear sRGB reflectance, each in [0, 1]
    // Linear sRGB emission as exitance, >= 0: glTF pi x emissiveFactor x emissiveStrength
    // (emissive is radiance), MTL Ke.
    std::array<double, 3> emissiveRgb{0, 0, 0};
    MaterialExtension spectral;
    // glTF textures (scene/texture.h), multiplying baseColor and emissiveRgb; the solve takes
    // each patch's mean, the image the texel (scene/surface_appearance.h).
    std::optional<TextureRef> baseColorTexture;
    std::optional<TextureRef> emissiveTexture;
    // glTF doubleSided: the back face is a surface too (a back patch per front patch).
    bool doubleSided = false;

    bool isEmissive() const;  // a non-zero emission spectrum or RGB emission
    bool isFluorescent() const;  // has a fluorescence description
};

// Overlays the members `overlay` sets onto `target`.
void mergeExtension(MaterialExtension& target, const MaterialExtension& overlay);

}  // namespace daisy
