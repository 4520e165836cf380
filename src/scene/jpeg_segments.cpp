#include "scene/jpeg_segments.h"

#include <cstddef>
#include <cstdint>

#include "core/strings.h"

namespace daisy {
namespace {

constexpr uint8_t kMarker = 0xFF;
constexpr uint8_t kStartOfImage = 0xD8;
constexpr uint8_t kEndOfImage = 0xD9;
constexpr uint8_t kStartOfScan = 0xDA;
constexpr uint8_t kHuffmanTables = 0xC4;
constexpr int kMaxCodes = 256;

// The byte at `at`, 0 past the end (stb_image reads zeros at the end of its buffer).
uint8_t byteAt(std::string_view bytes, std::size_t at) {
    return at < bytes.size() ? static_cast<uint8_t>(bytes[at]) : 0;
}

bool isRestart(uint8_t marker) {
    return marker >= 0xD0 && marker <= 0xD7;
}

// Marker codes without a length field (T.81 table B.1): TEM, RSTn, SOI, EOI, and the stuffed 0.
bool hasNoLength(uint8_t marker) {
    return marker == 0x00 || marker == 0x01 || isRestart(marker) || marker == kStartOfImage ||
        marker == kEndOfImage;
}

// The tables of the DHT segment whose length field is at `at`, read as stb_image reads them:
// while the remaining length is positive, a class/id byte, 16 counts and their values.
Expected<void> checkTables(std::string_view bytes, std::size_t at) {
    long long remaining = (byteAt(bytes, at) << 8 | byteAt(bytes, at + 1)) - 2;
    std::size_t table = at + 2;
    while (remaining > 0) {
        int codes = 0;
        for (std::size_t k = 1; k <= 16; ++k)
            codes += byteAt(bytes, table + k);
        if (codes > kMaxCodes) {
            return Error{concat("the JPEG is corrupt: its Huffman table at byte ", table, " lists ",
                                codes, " codes, over the ", kMaxCodes, " a table holds")};
        }
        table += 17 + std::size_t(codes);
        remaining -= 17 + codes;
    }
    return {};
}

}  // namespace

Expected<void> checkJpegHuffmanTables(std::string_view bytes) {
    if (byteAt(bytes, 0) != kMarker || byteAt(bytes, 1) != kStartOfImage) return {};
    std::size_t at = 2;
    bool inScan = false;  // inside a scan's entropy-coded data
    while (at < bytes.size()) {
        // Bytes up to the next 0xFF: stb skips them between segments; in a scan they are data.
        if (byteAt(bytes, at) != kMarker) {
            ++at;
            continue;
        }
        std::size_t code = at + 1;
        while (code < bytes.size() && byteAt(bytes, code) == kMarker)
            ++code;  // fill bytes
        if (code >= bytes.size()) return {};
        const uint8_t marker = byteAt(bytes, code);
        at = code + 1;
        // In a scan, 0xFF 0x00 is a data byte and RSTn a restart; both keep the scan going.
        if (inScan && (marker == 0x00 || isRestart(marker))) continue;
        inScan = false;
        if (marker == kEndOfImage) return {};
        if (hasNoLength(marker)) continue;
        if (marker == kHuffmanTables) {
            if (auto checked = checkTables(bytes, at); !checked) return checked;
        }
        const std::size_t length = std::size_t(byteAt(bytes, at)) << 8 | byteAt(bytes, at + 1);
        if (length < 2) return {};  // stb refuses a segment shorter than its length field
        at += length;
        inScan = marker == kStartOfScan;
    }
    return {};
}

}  // namespace daisy
