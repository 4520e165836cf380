#pragma once
// The form-factor settings the GPU backend tests share.
#include "radiosity/form_factors.h"

namespace daisy::test {

// `method` with `rays` shadow rays per pair and no progress output.
inline FormFactorSettings quietSettings(FormFactorMethod method, int rays) {
    FormFactorSettings settings;
    settings.method = method;
    settings.raysPerPair = rays;
    settings.progress = false;
    return settings;
}

}  // namespace daisy::test
