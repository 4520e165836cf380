#include "pipeline/channel_layout.h"

#include <numbers>

namespace daisy {

std::vector<float> radiosityChannels(const WavelengthSet& set, std::span<const double> b,
                                     bool spectral) {
    const std::size_t m = set.size(), n = b.size() / m;
    const ChannelLayout layout{m, spectral};
    const std::size_t channels = std::size_t(layout.count());
    std::vector<float> values(n * channels);
    std::vector<double> radiance(m);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t k = 0; k < m; ++k)
            radiance[k] = b[i * m + k] / std::numbers::pi;
        float* out = values.data() + i * channels;
        if (spectral) {
            for (std::size_t k = 0; k < m; ++k)
                out[layout.radiance(k)] = static_cast<float>(radiance[k]);
        }
        const Xyz xyz = set.toXyz(radiance);
        out[layout.x()] = static_cast<float>(xyz[0]);
        out[layout.y()] = static_cast<float>(xyz[1]);
        out[layout.z()] = static_cast<float>(xyz[2]);
        out[layout.coverage()] = 1.0f;
    }
    return values;
}

}  // namespace daisy
