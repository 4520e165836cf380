#include "bench/image_error.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "image/exposure.h"
#include "image/renderer.h"
#include "spectral/color.h"

namespace daisy {

namespace {

bool kept(const std::vector<uint8_t>& mask, std::size_t p) {
    return mask.empty() || mask[p] != 0;
}

std::vector<Lab> displayedLab(const Image& xyz, double exposureScale) {
    Image three(xyz.width, xyz.height, 3);
    for (std::size_t p = 0; p < std::size_t(xyz.width) * xyz.height; ++p)
        for (int c = 0; c < 3; ++c)
            three.pixels[p * 3 + c] = xyz.pixels[p * xyz.channels + c];
    const std::vector<uint8_t> srgb = toSrgb8(xyzToLinearSrgb(three, exposureScale));
    std::vector<Lab> lab(srgb.size() / 3);
    for (std::size_t p = 0; p < lab.size(); ++p)
        lab[p] = srgb8ToLab({srgb[p * 3], srgb[p * 3 + 1], srgb[p * 3 + 2]});
    return lab;
}

double meanReferenceY(const Image& referenceXyz, const std::vector<uint8_t>& mask) {
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t p = 0; p < std::size_t(referenceXyz.width) * referenceXyz.height; ++p) {
        if (!kept(mask, p)) continue;
        sum += referenceXyz.pixels[p * referenceXyz.channels + 1];
        ++count;
    }
    return count ? sum / double(count) : 0;
}

}  // namespace

ImageError compareImages(const Image& xyz, const Image& referenceXyz,
                         const std::vector<uint8_t>& mask, double exposureScale,
                         const Image* referenceVarianceY) {
    DAISY_CHECK(xyz.width == referenceXyz.width && xyz.height == referenceXyz.height);
    DAISY_CHECK(xyz.channels >= 3 && referenceXyz.channels >= 3);
    const std::size_t pixels = std::size_t(xyz.width) * xyz.height;
    DAISY_CHECK(mask.empty() || mask.size() == pixels);
    ImageError error;
    double squared = 0, variance = 0;
    const std::vector<Lab> a = displayedLab(xyz, exposureScale);
    const std::vector<Lab> b = displayedLab(referenceXyz, exposureScale);
    std::vector<double> deltas;
    double sum76 = 0, sum00 = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
        if (!kept(mask, p)) continue;
        const double d = double(xyz.pixels[p * xyz.channels + 1]) -
            referenceXyz.pixels[p * referenceXyz.channels + 1];
        squared += d * d;
        if (referenceVarianceY) variance += referenceVarianceY->pixels[p];
        sum76 += deltaE76(a[p], b[p]);
        deltas.push_back(deltaE2000(a[p], b[p]));
        sum00 += deltas.back();
        ++error.pixels;
    }
    const double meanY = meanReferenceY(referenceXyz, mask);
    if (error.pixels == 0 || meanY <= 0) return error;
    const double n = double(error.pixels);
    error.relativeRmsY = std::sqrt(squared / n) / meanY;
    error.relativeRmsYDenoised = std::sqrt(std::max(0.0, (squared - variance) / n)) / meanY;
    error.meanDeltaE76 = sum76 / n;
    error.meanDeltaE2000 = sum00 / n;
    const std::size_t at = std::min(deltas.size() - 1, deltas.size() * 95 / 100);
    std::nth_element(deltas.begin(), deltas.begin() + std::ptrdiff_t(at), deltas.end());
    error.p95DeltaE2000 = deltas[at];
    return error;
}

Expected<std::vector<uint8_t>> emitterMask(const PatchMesh& patches, const RadiositySystem& system,
                                           const Camera& camera, int width, int height, int grow) {
    std::vector<float> corners(patches.patchCount() * 3);
    for (uint32_t p = 0; p < patches.patchCount(); ++p) {
        const double* e = system.emissionRow(p);
        const bool emits =
            std::any_of(e, e + system.wavelengthCount, [](double v) { return v > 0; });
        for (int c = 0; c < 3; ++c)
            corners[p * 3 + std::size_t(c)] = emits ? 1.0f : 0.0f;
    }
    RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.samplesPerPixel = 16;
    const float background = 0;
    auto seen = renderCornerValues(patches, camera, settings, corners, 1, {&background, 1});
    if (!seen) return seen.error();
    std::vector<uint8_t> mask(std::size_t(width) * height, 1);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            if (*seen->at(x, y) <= 0) continue;
            for (int dy = -grow; dy <= grow; ++dy) {
                for (int dx = -grow; dx <= grow; ++dx) {
                    const int u = x + dx, v = y + dy;
                    if (u >= 0 && v >= 0 && u < width && v < height)
                        mask[std::size_t(v) * width + u] = 0;
                }
            }
        }
    }
    return mask;
}

std::vector<uint8_t> errorImageRgb8(const Image& xyz, const Image& referenceXyz,
                                    const std::vector<uint8_t>& mask, double fullScale) {
    const std::size_t pixels = std::size_t(xyz.width) * xyz.height;
    const double meanY = meanReferenceY(referenceXyz, mask);
    std::vector<uint8_t> rgb(pixels * 3);
    for (std::size_t p = 0; p < pixels; ++p) {
        if (!kept(mask, p)) {
            rgb[p * 3 + 2] = 96;
            continue;
        }
        const double d = std::abs(double(xyz.pixels[p * xyz.channels + 1]) -
                                  referenceXyz.pixels[p * referenceXyz.channels + 1]);
        const double v = meanY > 0 ? std::clamp(d / meanY / fullScale, 0.0, 1.0) : 0.0;
        const auto level = static_cast<uint8_t>(std::lround(255 * v));
        rgb[p * 3] = rgb[p * 3 + 1] = rgb[p * 3 + 2] = level;
    }
    return rgb;
}

}  // namespace daisy
