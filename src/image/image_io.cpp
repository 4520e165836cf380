#include "image/image_io.h"

#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/check.h"
#include "core/strings.h"

// The stb implementations are compiled here, static to this file, so they cannot clash with the
// copy TinyGLTF's shared library brings in.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#define STBI_WRITE_NO_STDIO
#include <stb_image_write.h>
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#include <stb_image.h>

namespace daisy {

namespace {

static_assert(std::endian::native == std::endian::little, "PFM writer assumes little-endian");

const char* const kSpectralPrefix = "S0.";

// An OpenEXR output stream over an open C stream, so writeExr can go through
// writeFileAtomically like the other writers. Errors are left to the stream's error flag.
class CFileOStream final : public Imf::OStream {
public:
    CFileOStream(std::FILE* file, const std::string& path)
        : Imf::OStream(path.c_str()), file_(file) {}
    void write(const char c[], int n) override {
        if (std::fwrite(c, 1, std::size_t(n), file_) != std::size_t(n))
            throw std::runtime_error(std::string("write failed: ") + std::strerror(errno));
    }
    uint64_t tellp() override { return uint64_t(std::ftell(file_)); }
    void seekp(uint64_t position) override {
        if (std::fseek(file_, long(position), SEEK_SET) != 0)
            throw std::runtime_error(std::string("seek failed: ") + std::strerror(errno));
    }

private:
    std::FILE* file_;
};

std::vector<std::string> exrChannelNames(const Image& image) {
    if (!image.channelNames.empty()) {
        DAISY_CHECK(image.channelNames.size() == std::size_t(image.channels));
        return image.channelNames;
    }
    if (image.channels == 3) return {"R", "G", "B"};
    if (image.channels == 1) return {"Y"};
    std::vector<std::string> names;
    for (int c = 0; c < image.channels; ++c)
        names.push_back(concat("C", c));
    return names;
}

Expected<std::string> readWholeFile(const std::string& path) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                         &std::fclose);
    if (!file) return Error{concat(path, ": cannot read: ", std::strerror(errno))};
    std::string data;
    char buffer[65536];
    std::size_t count;
    while ((count = std::fread(buffer, 1, sizeof buffer, file.get())) > 0)
        data.append(buffer, count);
    if (std::ferror(file.get()))
        return Error{concat(path, ": read failed: ", std::strerror(errno))};
    return data;
}

}  // namespace

Expected<void> writePng(const std::string& path, int width, int height,
                        std::span<const uint8_t> srgb8) {
    DAISY_CHECK(width > 0 && height > 0);
    DAISY_CHECK(srgb8.size() == std::size_t(width) * height * 3);
    return writeFileAtomically(path, [&](std::FILE* file) -> std::string {
        const auto sink = [](void* context, void* data, int size) {
            std::fwrite(data, 1, std::size_t(size), static_cast<std::FILE*>(context));
        };
        if (stbi_write_png_to_func(sink, file, width, height, 3, srgb8.data(), width * 3) == 0)
            return "PNG encoding failed";
        return "";
    });
}

Expected<void> writePfm(const std::string& path, const Image& linearRgb) {
    DAISY_CHECK(linearRgb.channels == 3);
    return writeFileAtomically(path, [&](std::FILE* file) -> std::string {
        // Scale -1: little-endian floats, unit scale.
        std::fprintf(file, "PF\n%d %d\n-1.0\n", linearRgb.width, linearRgb.height);
        for (int y = linearRgb.height - 1; y >= 0; --y)
            std::fwrite(linearRgb.at(0, y), sizeof(float), std::size_t(linearRgb.width) * 3, file);
        return "";
    });
}

std::string spectralChannelName(double wavelengthNm) {
    char digits[64];
    std::snprintf(digits, sizeof digits, "%.6f", wavelengthNm);
    for (char* c = digits; *c != 0; ++c) {
        if (*c == '.') *c = ',';
    }
    return std::string(kSpectralPrefix) + digits + "nm";
}

Expected<void> writeExr(const std::string& path, const Image& image) {
    DAISY_CHECK(image.width > 0 && image.height > 0 && image.channels > 0);
    const std::vector<std::string> names = exrChannelNames(image);
    return writeFileAtomically(path, [&](std::FILE* file) -> std::string {
        try {
            Imf::Header header(image.width, image.height);
            header.compression() = Imf::ZIP_COMPRESSION;
            bool spectral = false;
            Imf::FrameBuffer frameBuffer;
            const std::size_t xStride = sizeof(float) * std::size_t(image.channels);
            const std::size_t yStride = xStride * std::size_t(image.width);
            for (int c = 0; c < image.channels; ++c) {
                header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
                // OpenEXR takes a non-const base pointer for output slices but only reads it.
                char* base = reinterpret_cast<char*>(const_cast<float*>(image.pixels.data() + c));
                frameBuffer.insert(names[c], Imf::Slice(Imf::FLOAT, base, xStride, yStride));
                spectral = spectral || names[c].rfind(kSpectralPrefix, 0) == 0;
            }
            if (spectral) {
                // Fichet, Pacanowski & Wilkie 2021, "An OpenEXR Layout for Spectral Images",
                // JCGT 10(3): the layout version and the units of the emissive (S0) channels.
                header.insert("spectralLayoutVersion", Imf::StringAttribute("1.0"));
                header.insert("emissiveUnits", Imf::StringAttribute("W.m^-2.sr^-1"));
            }
            CFileOStream stream(file, path);
            Imf::OutputFile output(stream, header);
            output.setFrameBuffer(frameBuffer);
            output.writePixels(image.height);
        } catch (const std::exception& e) {
            return concat("EXR write failed: ", e.what());
        }
        return "";
    });
}

Expected<Image> readPng(const std::string& path) {
    auto data = readWholeFile(path);
    if (!data) return data.error();
    int width = 0, height = 0, fileChannels = 0;
    stbi_uc* pixels = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(data->data()),
                                            int(data->size()), &width, &height, &fileChannels, 3);
    if (pixels == nullptr) return Error{concat(path, ": not a PNG (", stbi_failure_reason(), ")")};
    Image image(width, height, 3);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = pixels[i];
    stbi_image_free(pixels);
    return image;
}

Expected<Image> readPfm(const std::string& path) {
    auto data = readWholeFile(path);
    if (!data) return data.error();
    // Header: "PF" or "Pf", whitespace, width, height, scale, then one whitespace character.
    char magic[3] = {};
    int width = 0, height = 0, headerBytes = 0;
    double scale = 0;
    if (std::sscanf(data->c_str(), "%2s %d %d %lf%n", magic, &width, &height, &scale,
                    &headerBytes) != 4 ||
        (std::strcmp(magic, "PF") != 0 && std::strcmp(magic, "Pf") != 0) || width <= 0 ||
        height <= 0 || scale == 0 || std::size_t(headerBytes) >= data->size()) {
        return Error{concat(path, ": not a PFM file (bad header)")};
    }
    const int channels = magic[1] == 'F' ? 3 : 1;
    const std::size_t offset = std::size_t(headerBytes) + 1;
    const std::size_t values = std::size_t(width) * height * channels;
    if (data->size() - offset < values * sizeof(float)) {
        return Error{concat(path, ": PFM data too short for ", width, " x ", height, " x ",
                            channels, " floats")};
    }
    Image image(width, height, channels);
    const bool swap = scale > 0;  // positive scale: big-endian
    for (int y = 0; y < height; ++y) {
        const char* row =
            data->data() + offset + std::size_t(height - 1 - y) * width * channels * sizeof(float);
        for (std::size_t i = 0; i < std::size_t(width) * channels; ++i) {
            uint32_t bits;
            std::memcpy(&bits, row + i * sizeof(float), sizeof bits);
            if (swap) bits = __builtin_bswap32(bits);
            image.at(0, y)[i] = std::bit_cast<float>(bits);
        }
    }
    return image;
}

Expected<Image> readExr(const std::string& path,
                        std::map<std::string, std::string>* stringAttributes) {
    try {
        Imf::InputFile input(path.c_str());
        const Imf::Header& header = input.header();
        const Imath::Box2i window = header.dataWindow();
        const int width = window.max.x - window.min.x + 1;
        const int height = window.max.y - window.min.y + 1;
        std::vector<std::string> names;
        for (auto channel = header.channels().begin(); channel != header.channels().end();
             ++channel)
            names.emplace_back(channel.name());
        Image image(width, height, int(names.size()));
        image.channelNames = names;
        Imf::FrameBuffer frameBuffer;
        const std::size_t xStride = sizeof(float) * names.size();
        const std::size_t yStride = xStride * std::size_t(width);
        // OpenEXR addresses pixel (x, y) of the data window at base + x * xStride + y * yStride.
        char* origin = reinterpret_cast<char*>(image.pixels.data()) -
            std::ptrdiff_t(window.min.x) * std::ptrdiff_t(xStride) -
            std::ptrdiff_t(window.min.y) * std::ptrdiff_t(yStride);
        for (std::size_t c = 0; c < names.size(); ++c) {
            frameBuffer.insert(
                names[c], Imf::Slice(Imf::FLOAT, origin + c * sizeof(float), xStride, yStride));
        }
        input.setFrameBuffer(frameBuffer);
        input.readPixels(window.min.y, window.max.y);
        if (stringAttributes != nullptr) {
            stringAttributes->clear();
            for (auto attribute = header.begin(); attribute != header.end(); ++attribute) {
                const auto* text =
                    dynamic_cast<const Imf::StringAttribute*>(&attribute.attribute());
                if (text != nullptr) (*stringAttributes)[attribute.name()] = text->value();
            }
        }
        return image;
    } catch (const std::exception& e) {
        return Error{concat(path, ": cannot read EXR: ", e.what())};
    }
}

}  // namespace daisy
