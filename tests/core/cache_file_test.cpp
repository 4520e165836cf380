// The binary cache-file layer (core/cache_file.h): its hashes against their specifications and
// reference implementations, the header layout docs/cache.md documents, a round trip, and every
// kind of bad file rejected with a one-line reason.
#include "core/cache_file.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "test_util.h"

namespace daisy {
namespace {

namespace fs = std::filesystem;

std::span<const std::byte> bytesOfText(std::string_view text) {
    return std::as_bytes(std::span(text.data(), text.size()));
}

// FNV-1a 128 of "" is the offset basis by definition (draft-eastlake-fnv); "a" and "foobar" as
// an independent Python implementation of the definition gives them:
// h = 0x6c62272e07bb014262b821756295c58d; for each byte: h = ((h ^ byte) * (2^88 + 0x13b)) % 2^128.
TEST(BinaryFileHash, Fnv1a128MatchesTheSpecification) {
    const auto fnv = [](std::string_view text) {
        Fnv1a128 hash;
        hash.update(bytesOfText(text));
        return hash.digest().hex();
    };
    EXPECT_EQ(fnv(""), "6c62272e07bb014262b821756295c58d");
    EXPECT_EQ(fnv("a"), "d228cb696f1a8caf78912b704e4a8964");
    EXPECT_EQ(fnv("foobar"), "343e1662793c64bf6f0d3597ba446f18");
}

// The test vectors of draft-eastlake-fnv for FNV-1a 64 ("" is the offset basis).
TEST(BinaryFileHash, Fnv1a64MatchesTheSpecification) {
    const auto fnv = [](std::string_view text) {
        Fnv1a64 hash;
        hash.update(text);
        return hash.digest();
    };
    EXPECT_EQ(fnv(""), 0xcbf29ce484222325ull);
    EXPECT_EQ(fnv("a"), 0xaf63dc4c8601ec8cull);
    EXPECT_EQ(fnv("foobar"), 0x85944171f73967e8ull);
}

// XXH64 reference values from libxxhash 0.8.1 (XXH64(data, len, seed), called through Python
// ctypes), an implementation independent of ours.
TEST(BinaryFileHash, Xxh64MatchesTheReferenceLibrary) {
    EXPECT_EQ(xxh64(bytesOfText("")), 0xef46db3751d8e999ull);
    EXPECT_EQ(xxh64(bytesOfText("a")), 0xd24ec4f1a98c6e5bull);
    EXPECT_EQ(xxh64(bytesOfText("abc")), 0x44bc2cf5ad770999ull);
    EXPECT_EQ(xxh64(bytesOfText("abc"), 0x9E3779B97F4A7C15ull), 0x2ed0f59d6b43ac8bull);
    std::string long771;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 256; ++c)
            long771.push_back(static_cast<char>(c));
    }
    long771 += "xyz";
    EXPECT_EQ(xxh64(bytesOfText(long771)), 0xe921a1b45bd779f8ull);
    EXPECT_EQ(xxh64(bytesOfText(long771), 0x9E3779B97F4A7C15ull), 0x179ca0201a65d20eull);
    // Streaming in uneven pieces gives the one-shot digest.
    for (std::size_t piece : {1u, 7u, 31u, 33u, 100u}) {
        Xxh64 hash;
        for (std::size_t at = 0; at < long771.size(); at += piece)
            hash.update(bytesOfText(std::string_view(long771).substr(at, piece)));
        EXPECT_EQ(hash.digest(), 0xe921a1b45bd779f8ull) << piece;
    }
}

const CacheFileFormat kFormat{{'D', 'A', 'I', 'S', 'Y', 'T', 'S', 'T'}, 7, "test cache file"};
const Hash128 kKey{0x0123456789abcdefull, 0xfedcba9876543210ull};

using test::readBytes;
using test::writeBytes;

// An entry of kFormat: a uint32 tag, then `values` doubles (counts[0] says how many).
class BinaryFile : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = test::testTempDir();
        path_ = dir_ / "entry.bin";
        for (int k = 0; k < 100; ++k)
            values_.push_back(k * 0.25 - 3);
        CacheFileHeader header;
        header.magic = kFormat.magic;
        header.version = kFormat.version;
        header.detail = 42;
        header.key = kKey;
        header.counts = {values_.size(), 9};
        const std::span<const std::byte> payload[] = {bytesOf(tag_), bytesOf(values_)};
        EXPECT_EQ(cacheFileBytes(payload), 64u + 4 + 800);
        const auto written = writeCacheFile(path_, header, payload);
        ASSERT_TRUE(written.ok()) << written.error().message;
        bytes_ = readBytes(path_);
    }

    // Reads the entry at path_ back as kFormat with `key`; the first problem met, "" if none.
    std::string readBack(const Hash128& key = kKey) {
        CacheFileReader reader = CacheFileReader::open(path_, kFormat, key);
        if (reader.status() != CacheFileReader::Status::Open) return reader.problem();
        uint32_t tag = 0;
        std::vector<double> values;
        if (!reader.read(&tag, 4) || !reader.readArray(values, reader.header().counts[0])) {
            return reader.finish();
        }
        if (std::string problem = reader.finish(); !problem.empty()) return problem;
        EXPECT_EQ(tag, tag_);
        EXPECT_EQ(values, values_);
        EXPECT_EQ(reader.header().detail, 42u);
        EXPECT_EQ(reader.header().counts[1], 9u);
        return {};
    }

    void expectRejected(const std::string& bytes, const std::string& reason) {
        writeBytes(path_, bytes);
        const std::string problem = readBack();
        EXPECT_NE(problem.find(reason), std::string::npos) << problem;
        EXPECT_EQ(problem.find('\n'), std::string::npos) << problem;
    }

    fs::path dir_, path_;
    uint32_t tag_ = 0xdecafbad;
    std::vector<double> values_;
    std::string bytes_;
};

TEST_F(BinaryFile, RoundTripsAndLeavesNoTemporary) {
    EXPECT_EQ(readBack(), "");
    EXPECT_EQ(bytes_.size(), 64u + 4 + 800);
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_))
        names.push_back(entry.path().filename().string());
    EXPECT_EQ(names, std::vector<std::string>{"entry.bin"});
}

// The header at the offsets docs/cache.md lists, its checksums XXH64 of the spans it names.
TEST_F(BinaryFile, HeaderIsTheDocumentedLayout) {
    const auto u32 = [&](std::size_t at) {
        uint32_t v;
        std::memcpy(&v, bytes_.data() + at, 4);
        return v;
    };
    const auto u64 = [&](std::size_t at) {
        uint64_t v;
        std::memcpy(&v, bytes_.data() + at, 8);
        return v;
    };
    EXPECT_EQ(bytes_.substr(0, 8), "DAISYTST");
    EXPECT_EQ(u32(8), 7u);
    EXPECT_EQ(u32(12), 42u);
    EXPECT_EQ(u64(16), kKey.hi);
    EXPECT_EQ(u64(24), kKey.lo);
    EXPECT_EQ(u64(32), 100u);
    EXPECT_EQ(u64(40), 9u);
    EXPECT_EQ(u64(48), xxh64(bytesOfText(std::string_view(bytes_).substr(64))));
    EXPECT_EQ(u64(56), xxh64(bytesOfText(std::string_view(bytes_).substr(0, 56))));
}

TEST_F(BinaryFile, MissingFileIsNotAProblem) {
    fs::remove(path_);
    const CacheFileReader reader = CacheFileReader::open(path_, kFormat, kKey);
    EXPECT_EQ(reader.status(), CacheFileReader::Status::Missing);
}

TEST_F(BinaryFile, FolderIsRejectedButNotRemovable) {
    const CacheFileReader reader = CacheFileReader::open(dir_, kFormat, kKey);
    EXPECT_EQ(reader.status(), CacheFileReader::Status::Rejected);
    EXPECT_FALSE(reader.removable());
}

TEST_F(BinaryFile, TruncatedFilesAreRejected) {
    expectRejected("", "empty file");
    expectRejected(bytes_.substr(0, 10), "truncated header (10 of 64 bytes)");
    expectRejected(bytes_.substr(0, 64), "file ended early while reading (truncated)");
    expectRejected(bytes_.substr(0, bytes_.size() - 1), "file ended early while reading");
    expectRejected(bytes_ + "x", "file is 869 bytes, its payload ends at 868");
}

TEST_F(BinaryFile, ChecksumMismatchesAreRejected) {
    std::string payload = bytes_;
    payload[100] ^= 0x01;
    expectRejected(payload, "payload checksum mismatch (file corrupt)");
    std::string header = bytes_;
    header[20] ^= 0x01;  // in the key: the header checksum fails before the key is compared
    expectRejected(header, "header checksum mismatch (file corrupt)");
}

TEST_F(BinaryFile, ForeignFilesAreRejected) {
    std::string magic = bytes_;
    magic[5] = 'X';
    expectRejected(magic, "not a DaisyRiot test cache file (bad magic)");
    std::string version = bytes_;
    version[8] = 6;
    expectRejected(version, "format version 6, this build reads version 7");
    writeBytes(path_, bytes_);
    const std::string problem = readBack({kKey.hi, kKey.lo ^ 1});
    EXPECT_NE(problem.find("holds the entry for key 0123456789abcdeffedcba9876543210"),
              std::string::npos)
        << problem;
}

TEST(BinaryFileWrite, UnwritableFolderIsAnError) {
    const fs::path dir = test::testTempDir();
    test::writeFile(dir, "file", "not a folder");
    CacheFileHeader header;
    header.magic = kFormat.magic;
    const auto written = writeCacheFile(dir / "file" / "entry.bin", header, {});
    ASSERT_FALSE(written.ok());
    EXPECT_NE(written.error().message.find("entry.bin"), std::string::npos);
}

}  // namespace
}  // namespace daisy
