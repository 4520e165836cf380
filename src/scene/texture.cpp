#include "scene/texture.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/strings.h"
#include "scene/jpeg_segments.h"
#include "spectral/color.h"

// stb_image compiled here, static to this file (image_io.cpp and TinyGLTF have their own).
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wshadow"
#endif
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#include <stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace daisy {
namespace {

// Wraps texel coordinate i into [0, size) by the glTF wrap mode.
int wrapIndex(long long i, int size, TextureWrap wrap) {
    const long long n = size;
    switch (wrap) {
        case TextureWrap::ClampToEdge:
            return static_cast<int>(std::clamp<long long>(i, 0, n - 1));
        case TextureWrap::MirroredRepeat: {
            const long long period = 2 * n;
            long long k = ((i % period) + period) % period;
            return static_cast<int>(k < n ? k : period - 1 - k);
        }
        default:
            return static_cast<int>(((i % n) + n) % n);
    }
}

// Texel coordinates far outside the image wrap the same as near ones; this keeps the integer
// conversion in range for any finite uv.
double reduce(double x) {
    constexpr double kLimit = 1 << 30;
    return std::isfinite(x) ? std::clamp(x, -kLimit, kLimit) : 0.0;
}

}  // namespace

std::array<double, 6> textureTransform(std::array<double, 2> offset, double rotation,
                                       std::array<double, 2> scale) {
    const double c = std::cos(rotation), s = std::sin(rotation);
    // T * R * S with R = [[c, s], [-s, c]] (KHR_texture_transform).
    return {c * scale[0], s * scale[1], offset[0], -s * scale[0], c * scale[1], offset[1]};
}

std::array<float, 3> sampleTexture(const TextureImage& image, const TextureRef& ref, double u,
                                   double v) {
    const auto& t = ref.transform;
    const double tu = t[0] * u + t[1] * v + t[2];
    const double tv = t[3] * u + t[4] * v + t[5];
    const double x = reduce(tu * image.width - 0.5);  // texel centres at half-integers
    const double y = reduce(tv * image.height - 0.5);
    const auto texel = [&](long long i, long long j) {
        const int col = wrapIndex(i, image.width, ref.wrapS);
        const int row = wrapIndex(j, image.height, ref.wrapT);
        return image.rgb.data() + (std::size_t(row) * std::size_t(image.width) + col) * 3;
    };
    if (ref.nearest) {
        const float* p = texel(std::llround(x), std::llround(y));
        return {p[0], p[1], p[2]};
    }
    const double x0 = std::floor(x), y0 = std::floor(y);
    const double fx = x - x0, fy = y - y0;
    const auto i = static_cast<long long>(x0), j = static_cast<long long>(y0);
    const float* a = texel(i, j);
    const float* b = texel(i + 1, j);
    const float* c = texel(i, j + 1);
    const float* d = texel(i + 1, j + 1);
    std::array<float, 3> out{};
    for (int k = 0; k < 3; ++k) {
        const double top = a[k] + (b[k] - a[k]) * fx;
        const double bottom = c[k] + (d[k] - c[k]) * fx;
        out[k] = static_cast<float>(top + (bottom - top) * fy);
    }
    return out;
}

namespace {

enum class ImageKind { Png, Jpeg, Other };

ImageKind imageKind(std::string_view bytes) {
    if (bytes.starts_with("\x89PNG\r\n\x1a\n")) return ImageKind::Png;
    if (bytes.starts_with("\xff\xd8\xff")) return ImageKind::Jpeg;
    return ImageKind::Other;
}

uint32_t bigEndian32(std::string_view bytes, std::size_t at) {
    uint32_t value = 0;
    for (std::size_t k = 0; k < 4; ++k)
        value = (value << 8) | static_cast<unsigned char>(bytes[at + k]);
    return value;
}

// What is wrong with an image stb_image cannot read, in words that name the format: stb tries
// every format in turn and reports the last one's complaint ("bad png sig" for a truncated
// JPEG), and refuses a PNG over 2^30 decoded bytes as "unknown image type".
std::string undecodable(std::string_view bytes) {
    constexpr const char* kRead = "; PNG and JPEG are read";
    if (bytes.empty()) return concat("the image is empty (0 bytes)", kRead);
    switch (imageKind(bytes)) {
        case ImageKind::Png:
            // IHDR: the first chunk, width and height at bytes 16 and 20, the colour type at 25.
            if (bytes.size() >= 26 && bytes.substr(12, 4) == "IHDR") {
                const uint64_t width = bigEndian32(bytes, 16), height = bigEndian32(bytes, 20);
                const auto colour = static_cast<unsigned char>(bytes[25]);
                const uint64_t channels = ((colour & 2) ? 3 : 1) + ((colour & 4) ? 1 : 0);
                if (width * height * channels > (uint64_t(1) << 30)) {
                    return concat("the PNG is ", width, " x ", height,
                                  ", over the 2^30 decoded bytes the PNG reader accepts");
                }
            }
            return concat("the PNG is corrupt or truncated (", formatBytes(double(bytes.size())),
                          ")");
        case ImageKind::Jpeg:
            return concat("the JPEG is corrupt or truncated (", formatBytes(double(bytes.size())),
                          ")");
        case ImageKind::Other:
            break;
    }
    std::string start;
    for (std::size_t k = 0; k < std::min<std::size_t>(bytes.size(), 4); ++k) {
        constexpr const char* kDigits = "0123456789abcdef";
        const auto byte = static_cast<unsigned char>(bytes[k]);
        start += concat(k ? " " : "", kDigits[byte >> 4], kDigits[byte & 15]);
    }
    return concat("not a PNG or JPEG (it starts with the bytes ", start, ")", kRead);
}

}  // namespace

Expected<TextureImage> decodeTextureImage(std::string_view bytes, bool srgb, LoadBudget& budget) {
    if (auto tables = checkJpegHuffmanTables(bytes); !tables) return tables.error();
    int width = 0, height = 0, channels = 0;
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int size = static_cast<int>(std::min<std::size_t>(bytes.size(), INT32_MAX));
    if (stbi_info_from_memory(data, size, &width, &height, &channels) == 0) {
        return Error{undecodable(bytes)};
    }
    // stb's 8-bit copy and the float one.
    const uint64_t decodedBytes = uint64_t(width) * uint64_t(height) * 3 * (1 + sizeof(float));
    if (auto charged = budget.charge(decodedBytes, concat("a ", width, " x ", height, " image"));
        !charged) {
        return charged.error();
    }
    stbi_uc* pixels = stbi_load_from_memory(data, size, &width, &height, &channels, 3);
    if (pixels == nullptr) return Error{undecodable(bytes)};
    TextureImage image;
    image.width = width;
    image.height = height;
    image.rgb.resize(std::size_t(width) * std::size_t(height) * 3);
    float table[256];
    for (int k = 0; k < 256; ++k)
        table[k] = static_cast<float>(srgb ? srgbDecode(k / 255.0) : k / 255.0);
    for (std::size_t k = 0; k < image.rgb.size(); ++k)
        image.rgb[k] = table[pixels[k]];
    stbi_image_free(pixels);
    return image;
}

}  // namespace daisy
