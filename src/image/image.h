#pragma once
// Float images: row-major from the top row, `channels` interleaved values per pixel.
#include <cstddef>
#include <string>
#include <vector>

namespace daisy {

struct Image {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<float> pixels;  // width * height * channels
    std::vector<std::string> channelNames;  // optional, one per channel (EXR layers)

    Image() = default;
    Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(std::size_t(w) * h * c) {}
    float* at(int x, int y) { return pixels.data() + (std::size_t(y) * width + x) * channels; }
    const float* at(int x, int y) const {
        return pixels.data() + (std::size_t(y) * width + x) * channels;
    }
};

}  // namespace daisy
