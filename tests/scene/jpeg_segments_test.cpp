// The JPEG Huffman-table check that runs before stb_image (scene/jpeg_segments.h): every DHT
// table stb could read, between segments or after a scan, is refused past 256 codes (ITU-T T.81
// B.2.4.2); bytes stb never reads as a segment (an APP payload) are not. The streams are built
// here byte by byte, so each expected offset is counted from the layout.
#include <gtest/gtest.h>

#include <string>

#include "scene/jpeg_segments.h"
#include "scene/load_budget.h"
#include "scene/texture.h"
#include "spectral/color.h"

namespace daisy {
namespace {

std::string segment(unsigned char marker, const std::string& body) {
    const std::size_t length = body.size() + 2;
    return std::string{'\xFF', char(marker), char(length >> 8), char(length & 0xFF)} + body;
}

// One Huffman table (class 0 DC or 1 AC, id 0) whose 16 counts are `counts`, all codes of
// length 1 in counts[0] and so on, followed by sum(counts) symbol bytes of 0.
std::string table(int tableClass, const std::string& counts) {
    int codes = 0;
    for (char c : counts)
        codes += static_cast<unsigned char>(c);
    return std::string(1, char(tableClass << 4)) + counts + std::string(std::size_t(codes), '\0');
}

std::string counts(int lengthOne, int lengthSixteen = 0) {
    std::string out(16, '\0');
    out[0] = char(lengthOne);
    out[15] = char(lengthSixteen);
    return out;
}

const std::string kStart = "\xFF\xD8";
const std::string kEnd = "\xFF\xD9";

// An 8 x 8 greyscale baseline JPEG of one block: DC difference 0 (level 128), then end of block.
// The same stream tools/make_fuzz_corpus.py writes for the texture seeds.
std::string greyJpeg(const std::string& extraSegments = "") {
    const std::string quantization = segment(0xDB, std::string(1, '\0') + std::string(64, '\1'));
    const std::string frame = segment(0xC0, std::string("\x08\x00\x08\x00\x08\x01\x01\x11\x00", 9));
    const std::string huffman =
        segment(0xC4, table(0, counts(1))) + segment(0xC4, table(1, counts(1)));
    const std::string scan = segment(0xDA, std::string("\x01\x01\x00\x00\x3F\x00", 6));
    return kStart + extraSegments + quantization + frame + huffman + scan + "\x3F" + kEnd;
}

TEST(JpegSegments, AcceptsAValidStreamThatStbDecodes) {
    const std::string jpeg = greyJpeg();
    EXPECT_TRUE(checkJpegHuffmanTables(jpeg));
    LoadBudget budget;
    auto image = decodeTextureImage(jpeg, true, budget);
    ASSERT_TRUE(image) << image.error().message;
    EXPECT_EQ(image->width, 8);
    EXPECT_EQ(image->height, 8);
    // Level 128 through the sRGB curve (IEC 61966-2-1): ((128/255 + 0.055) / 1.055)^2.4.
    EXPECT_FLOAT_EQ(image->rgb[0], float(srgbDecode(128.0 / 255.0)));
    EXPECT_NEAR(image->rgb[0], 0.2158605, 1e-6);
}

TEST(JpegSegments, RefusesATableOfMoreThan256CodesBeforeStbReadsIt) {
    // A DHT segment right after SOI: SOI (2 bytes), marker and length (4), so the table's
    // class/id byte is byte 6. 255 + 45 = 300 codes.
    const std::string jpeg = greyJpeg(segment(0xC4, table(1, counts(255, 45))));
    auto checked = checkJpegHuffmanTables(jpeg);
    ASSERT_FALSE(checked);
    const std::string message =
        "the JPEG is corrupt: its Huffman table at byte 6 lists 300 codes, "
        "over the 256 a table holds";
    EXPECT_EQ(checked.error().message, message);
    LoadBudget budget;
    auto image = decodeTextureImage(jpeg, true, budget);
    ASSERT_FALSE(image);
    EXPECT_EQ(image.error().message, message);
}

TEST(JpegSegments, ChecksEveryTableOfASegmentUpTo256) {
    // Two tables in one segment: 256 codes (the most T.81 allows) pass, the 257 after them not.
    // The second starts after the first's 17 + 256 bytes: 6 + 273 = 279.
    EXPECT_TRUE(checkJpegHuffmanTables(greyJpeg(segment(0xC4, table(0, counts(255, 1))))));
    const std::string two = segment(0xC4, table(0, counts(255, 1)) + table(1, counts(255, 2)));
    auto checked = checkJpegHuffmanTables(greyJpeg(two));
    ASSERT_FALSE(checked);
    EXPECT_EQ(checked.error().message,
              "the JPEG is corrupt: its Huffman table at byte 279 lists 257 codes, over the 256 a "
              "table holds");
}

TEST(JpegSegments, FindsATableAfterAScanAsAProgressiveJpegPlacesIt) {
    // After the scan's entropy-coded data (0x3F, a stuffed 0xFF 0x00 and a restart marker, which
    // do not end it) a DHT segment, then EOI. Its table follows EOI's old place (len - 2), the
    // 4 scan bytes and the segment's marker and length.
    std::string jpeg = greyJpeg();
    jpeg.insert(jpeg.size() - 2,
                std::string("\xFF\x00\xFF\xD0", 4) + segment(0xC4, table(1, counts(200, 100))));
    auto checked = checkJpegHuffmanTables(jpeg);
    ASSERT_FALSE(checked);
    const std::size_t expected = greyJpeg().size() - 2 + 4 + 4;
    EXPECT_EQ(checked.error().message,
              "the JPEG is corrupt: its Huffman table at byte " + std::to_string(expected) +
                  " lists 300 codes, over the 256 a table holds");
}

TEST(JpegSegments, SkipsPayloadsThatOnlyLookLikeATable) {
    // An APP1 segment holding 0xFF 0xC4 and counts of 16 x 255: stb skips it by its length.
    const std::string payload = std::string("\xFF\xC4\x01\x00\x00", 5) + std::string(16, '\xFF');
    EXPECT_TRUE(checkJpegHuffmanTables(greyJpeg(segment(0xE1, payload))));
    // Not a JPEG at all (a PNG signature), and a stream cut inside a segment.
    EXPECT_TRUE(checkJpegHuffmanTables("\x89PNG\r\n\x1a\n"));
    EXPECT_TRUE(checkJpegHuffmanTables(greyJpeg().substr(0, 30)));
}

}  // namespace
}  // namespace daisy
