#include "image/image_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "test_util.h"

namespace daisy {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> directoryListing(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir))
        names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

Image rampImage(int width, int height, int channels) {
    Image image(width, height, channels);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = 0.125f * float(i) - 1.5f;
    return image;
}

TEST(ImageIo, PngRoundTrip) {
    const fs::path dir = test::testTempDir();
    const std::string path = (dir / "out.png").string();
    std::vector<uint8_t> bytes(5 * 3 * 3);
    for (std::size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = uint8_t(i * 37 % 256);
    ASSERT_TRUE(writePng(path, 5, 3, bytes).ok());
    EXPECT_EQ(directoryListing(dir), std::vector<std::string>{"out.png"});  // no temporary left
    const auto image = readPng(path);
    ASSERT_TRUE(image.ok()) << image.error().message;
    ASSERT_EQ(image->width, 5);
    ASSERT_EQ(image->height, 3);
    ASSERT_EQ(image->channels, 3);
    for (std::size_t i = 0; i < bytes.size(); ++i)
        EXPECT_EQ(image->pixels[i], float(bytes[i])) << i;
}

TEST(ImageIo, PfmRoundTripAndLayout) {
    const fs::path dir = test::testTempDir();
    const std::string path = (dir / "out.pfm").string();
    const Image image = rampImage(4, 3, 3);
    ASSERT_TRUE(writePfm(path, image).ok());
    // PFM: "PF", width height, scale -1 (little-endian), then rows from the bottom up.
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const std::string header = "PF\n4 3\n-1.0\n";
    ASSERT_EQ(bytes.size(), header.size() + 4 * 3 * 3 * sizeof(float));
    EXPECT_EQ(bytes.substr(0, header.size()), header);
    float first;
    std::memcpy(&first, bytes.data() + header.size(), sizeof first);
    EXPECT_EQ(first, image.at(0, 2)[0]);  // bottom-left pixel first
    const auto back = readPfm(path);
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_EQ(back->width, 4);
    ASSERT_EQ(back->height, 3);
    ASSERT_EQ(back->channels, 3);
    EXPECT_EQ(back->pixels, image.pixels);
    const auto bad = readPfm(test::writeFile(dir, "bad.pfm", "P6\n1 1\n255\nabc"));
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("bad.pfm"), std::string::npos);
}

TEST(ImageIo, SpectralChannelNamesFollowFichet2021) {
    // Fichet, Pacanowski & Wilkie 2021: "S0." + wavelength with a comma + "nm".
    EXPECT_EQ(spectralChannelName(550), "S0.550,000000nm");
    EXPECT_EQ(spectralChannelName(456.4), "S0.456,400000nm");
}

TEST(ImageIo, ExrWithRgbAndSpectralChannelsReadsBack) {
    const fs::path dir = test::testTempDir();
    const std::string path = (dir / "out.exr").string();
    Image image = rampImage(6, 4, 5);
    image.channelNames = {"R", "G", "B", spectralChannelName(450), spectralChannelName(650.5)};
    ASSERT_TRUE(writeExr(path, image).ok());
    EXPECT_EQ(directoryListing(dir), std::vector<std::string>{"out.exr"});
    std::map<std::string, std::string> attributes;
    const auto back = readExr(path, &attributes);
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_EQ(back->width, 6);
    ASSERT_EQ(back->height, 4);
    ASSERT_EQ(back->channels, 5);
    // OpenEXR lists channels alphabetically.
    const std::vector<std::string> sorted = {"B", "G", "R", "S0.450,000000nm", "S0.650,500000nm"};
    EXPECT_EQ(back->channelNames, sorted);
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 6; ++x) {
            for (int c = 0; c < 5; ++c) {
                const auto it = std::find(sorted.begin(), sorted.end(), image.channelNames[c]);
                const int readChannel = int(it - sorted.begin());
                EXPECT_EQ(back->at(x, y)[readChannel], image.at(x, y)[c]);
            }
        }
    }
    EXPECT_EQ(attributes["spectralLayoutVersion"], "1.0");
    EXPECT_EQ(attributes["emissiveUnits"], "W.m^-2.sr^-1");
}

TEST(ImageIo, RgbExrHasNoSpectralAttributes) {
    const fs::path dir = test::testTempDir();
    const std::string path = (dir / "rgb.exr").string();
    ASSERT_TRUE(writeExr(path, rampImage(3, 2, 3)).ok());
    std::map<std::string, std::string> attributes;
    const auto back = readExr(path, &attributes);
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(back->channelNames, (std::vector<std::string>{"B", "G", "R"}));
    EXPECT_EQ(attributes.count("spectralLayoutVersion"), 0u);
    const auto missing = readExr((dir / "missing.exr").string());
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("missing.exr"), std::string::npos);
}

// Writers go through a temporary file: a target in a missing directory fails, the error names
// the file, and nothing is left behind.
TEST(ImageIo, FailedWritesNameTheFileAndLeaveNothing) {
    const fs::path dir = test::testTempDir();
    const Image rgb = rampImage(2, 2, 3);
    const std::vector<uint8_t> bytes(2 * 2 * 3, 128);
    for (const char* name : {"a.png", "a.pfm", "a.exr"}) {
        const std::string path = (dir / "missing" / name).string();
        Expected<void> result;
        if (fs::path(name).extension() == ".png") result = writePng(path, 2, 2, bytes);
        if (fs::path(name).extension() == ".pfm") result = writePfm(path, rgb);
        if (fs::path(name).extension() == ".exr") result = writeExr(path, rgb);
        ASSERT_FALSE(result.ok()) << name;
        EXPECT_NE(result.error().message.find(path), std::string::npos) << result.error().message;
    }
    EXPECT_TRUE(directoryListing(dir).empty());
}

}  // namespace
}  // namespace daisy
