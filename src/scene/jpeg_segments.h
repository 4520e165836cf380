#pragma once
// A JPEG's marker segments walked before stb_image sees them. Debian's stb_image 2.27 trusts a
// DHT table's 16 code counts: a table listing more than 256 codes (ITU-T T.81 B.2.4.2 allows at
// most 256 values) makes stbi__build_huffman and the value loop write past their 257- and
// 256-byte arrays. Every table stb could read is checked here first.
#include <string_view>

#include "core/expected.h"

namespace daisy {

// Error naming the byte offset of the first Huffman table that lists more than 256 codes, in
// any DHT segment stb_image could reach (between segments, and after each scan's entropy-coded
// data); success for every other input, JPEG or not (stb's own checks handle the rest).
Expected<void> checkJpegHuffmanTables(std::string_view bytes);

}  // namespace daisy
