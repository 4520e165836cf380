#include "scene/material.h"

namespace daisy {

bool Material::isEmissive() const {
    if (spectral.emission) return spectral.emission->scale > 0;
    return emissiveRgb[0] > 0 || emissiveRgb[1] > 0 || emissiveRgb[2] > 0;
}

bool Material::isFluorescent() const {
    return spectral.fluorescence.has_value();
}

void mergeExtension(MaterialExtension& target, const MaterialExtension& overlay) {
    if (overlay.reflectance) target.reflectance = overlay.reflectance;
    if (overlay.emission) target.emission = overlay.emission;
    if (overlay.fluorescence) target.fluorescence = overlay.fluorescence;
    if (overlay.removesFluorescence) target.fluorescence.reset();
}

}  // namespace daisy
