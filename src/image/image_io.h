#pragma once
// Image files (DESIGN.md section 7). Every writer writes to a temporary name beside the target
// and renames it (core/atomic_file.h), so a failure leaves no partial image. Errors name the
// file.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/expected.h"
#include "image/image.h"

namespace daisy {

// PNG, 8-bit sRGB, 3 channels (stb_image_write).
Expected<void> writePng(const std::string& path, int width, int height,
                        std::span<const uint8_t> srgb8);

// PFM (Portable Float Map, "PF", little-endian, rows bottom to top), 3 channels linear.
Expected<void> writePfm(const std::string& path, const Image& linearRgb);

// OpenEXR, 32-bit float, ZIP compression. `image.channelNames` name the channels (R, G, B for
// linear sRGB; spectral channels as spectralChannelName). Header attributes: the layout version
// attribute of Fichet et al. 2021 when spectral channels are present, and units.
Expected<void> writeExr(const std::string& path, const Image& image);

// Emissive spectral channel name of Fichet, Pacanowski & Wilkie 2021, "An OpenEXR Layout for
// Spectral Images", JCGT 10(3): Stokes component S0, the wavelength with a comma as decimal
// separator and its unit, e.g. 550 nm -> "S0.550,000000nm".
std::string spectralChannelName(double wavelengthNm);

// Readers for tests and tools: PNG (8-bit, 3 channels as 0..255 floats) and PFM.
Expected<Image> readPng(const std::string& path);
Expected<Image> readPfm(const std::string& path);

}  // namespace daisy
