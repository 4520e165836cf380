#pragma once
// Image error against a reference image: relative RMS of luminance and the mean
// CIE76 / CIEDE2000 colour differences as displayed, over the pixels a mask keeps. The mask
// leaves out the emitters' pixels and a neighbourhood around them, where an image is mostly
// light-source edge (as a comparison with Cycles does too).
#include <cstdint>
#include <vector>

#include "geometry/patch_mesh.h"
#include "image/image.h"
#include "radiosity/radiosity_system.h"
#include "scene/scene.h"

namespace daisy {

struct ImageError {
    // sqrt(mean (Y - Y_ref)^2) / mean Y_ref over the kept pixels.
    double relativeRmsY = 0;
    // The same with the reference's own noise taken out: E[(Y - Y_ref)^2] = bias^2 + var(Y_ref)
    // for a reference independent of the image, so sqrt(max(0, mean (Y - Y_ref)^2 - mean var))
    // / mean Y_ref estimates the error against the converged answer. Equal to relativeRmsY
    // without a variance image.
    double relativeRmsYDenoised = 0;
    double meanDeltaE76 = 0;  // as displayed at the exposure given, 8-bit sRGB, under D65
    double meanDeltaE2000 = 0;
    double p95DeltaE2000 = 0;
    std::size_t pixels = 0;  // pixels kept
};

// xyz and referenceXyz: X Y Z in their first three channels (more are ignored), the same size.
// mask: one byte per pixel, nonzero = compare (empty = every pixel). referenceVarianceY: one
// channel, the variance of each reference pixel's Y (pathtrace/path_tracer.h), or null.
// exposureScale: multiplies both images before display (the reference's exposure).
ImageError compareImages(const Image& xyz, const Image& referenceXyz,
                         const std::vector<uint8_t>& mask, double exposureScale,
                         const Image* referenceVarianceY = nullptr);

// The mask of compareImages that leaves out every pixel where a 4 x 4 grid of camera rays sees
// an emitting patch (nonzero E), grown by `grow` pixels in each direction (a square).
Expected<std::vector<uint8_t>> emitterMask(const PatchMesh& patches, const RadiositySystem& system,
                                           const Camera& camera, int width, int height,
                                           int grow = 2);

// |Y - Y_ref| / mean Y_ref as an 8-bit grey image (white = `fullScale`, e.g. 0.1 = 10%);
// masked-out pixels are drawn dark blue.
std::vector<uint8_t> errorImageRgb8(const Image& xyz, const Image& referenceXyz,
                                    const std::vector<uint8_t>& mask, double fullScale);

}  // namespace daisy
