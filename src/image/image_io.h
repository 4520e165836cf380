#pragma once
// Image files (DESIGN.md section 7). Every writer writes to a temporary name beside the target
// and renames it (core/atomic_file.h), so a failure leaves no partial image. Errors name the
// file.
#include <cstdint>
#include <map>
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

// OpenEXR, 32-bit float, ZIP compression, scan lines top to bottom. `image.channelNames` name
// the channels (R, G, B for linear sRGB; spectral channels as spectralChannelName; keep R, G, B
// beside them so ordinary viewers show the image); without names a 3-channel image is R, G, B
// and a 1-channel image Y. When a spectral channel ("S0." prefix) is present the header carries
// the layout's string attributes (Fichet et al. 2021, as their reference code afichet/spectral-exr
// and pbrt-v4's SpectralFilm write them): spectralLayoutVersion = "1.0" and emissiveUnits =
// "W.m^-2.sr^-1". The values are DaisyRiot's radiance in the scene's emission units.
Expected<void> writeExr(const std::string& path, const Image& image);

// Emissive spectral channel name of Fichet, Pacanowski & Wilkie 2021, "An OpenEXR Layout for
// Spectral Images", JCGT 10(3): Stokes component S0, the wavelength with a comma as decimal
// separator and its unit, e.g. 550 nm -> "S0.550,000000nm".
std::string spectralChannelName(double wavelengthNm);

// Readers for tests and tools: PNG (8-bit, converted to 3 channels as 0..255 floats), PFM ("PF"
// 3 channels or "Pf" 1 channel, either byte order), and EXR (every channel as float, with its
// name, in the file's (alphabetical) channel order; the header's string attributes go to
// `stringAttributes` when given).
Expected<Image> readPng(const std::string& path);
Expected<Image> readPfm(const std::string& path);
Expected<Image> readExr(const std::string& path,
                        std::map<std::string, std::string>* stringAttributes = nullptr);

}  // namespace daisy
