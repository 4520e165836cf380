#include "spectral/round_trip.h"

#include "core/check.h"
#include "spectral/spectrum.h"

namespace daisy {

ReflectanceRoundTrip::ReflectanceRoundTrip(const WavelengthSet& set,
                                           const RgbToSpectrumTable& table, bool polish)
    : set_(set), table_(table), polish_(polish) {
    auto d65 = illuminantPreset("D65");
    DAISY_CHECK(d65.ok());
    illuminant_ = sampleSpectrum(set, *d65, SpectrumRole::Emission);
}

std::vector<double> ReflectanceRoundTrip::samples(const Rgb& rgb) const {
    const SigmoidPolynomial shape = polish_ ? rgbToReflectance(rgb, table_) : table_.lookup(rgb);
    return sampleSpectrum(set_, Spectrum::reflectance(shape), SpectrumRole::Reflectance);
}

Xyz ReflectanceRoundTrip::xyz(const Rgb& rgb) const {
    return set_.reflectanceToXyz(samples(rgb), illuminant_);
}

Xyz ReflectanceRoundTrip::whiteXyz() const {
    return set_.reflectanceToXyz(std::vector<double>(set_.size(), 1.0), illuminant_);
}

}  // namespace daisy
