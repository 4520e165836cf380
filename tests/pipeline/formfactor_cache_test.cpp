#include "pipeline/formfactor_cache.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "backend/backend.h"
#include "scene/load_scene.h"
#include "test_util.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

namespace fs = std::filesystem;

// A non-trivial F: the closed unit cube room, 3 x 3 quads a face (108 patches), plus a square
// blocker inside it, built once with the cpu backend.
struct Built {
    PatchMesh patches;
    FormFactorSettings settings;
    FormFactorResult result;
};

const Built& built() {
    static const Built instance = [] {
        Built b;
        TriangleMesh mesh = verify::unitCubeRoom(3);
        verify::addGrid(mesh, {0.2, 0.2, 0.5}, {0.6, 0, 0}, {0, 0.6, 0}, 2, 2);
        b.patches = verify::patchesOf(mesh);
        b.settings.progress = false;
        b.result = std::move(makeCpuBackend()->buildFormFactors(b.patches, b.settings).value());
        return b;
    }();
    return instance;
}

FormFactorKey builtKey() {
    return formFactorKey(built().patches, built().settings, "cpu");
}

using test::readBytes;
using test::writeBytes;

template <typename T>
void put(std::string& bytes, std::size_t offset, T value) {
    std::memcpy(bytes.data() + offset, &value, sizeof(T));
}

uint64_t checksumOf(const std::string& bytes, std::size_t offset, std::size_t count) {
    return xxh64(std::as_bytes(std::span(bytes.data() + offset, count)));
}

// Recomputes both checksums as docs/cache.md defines them (payload: XXH64 of bytes 64.. at
// offset 48; header: XXH64 of bytes 0..55 at offset 56), so a test can forge a "valid" file.
void reseal(std::string& bytes) {
    put(bytes, 48, checksumOf(bytes, 64, bytes.size() - 64));
    put(bytes, 56, checksumOf(bytes, 0, 56));
}

// The directory's entries, by name.
// FormFactorCache::describe of the header of the file at `path`.
std::string describeEntry(const fs::path& path) {
    CacheHeaderBytes bytes{};
    std::ifstream(path, std::ios::binary).read(reinterpret_cast<char*>(bytes.data()), 64);
    return FormFactorCache::describe(decodeCacheHeader(bytes));
}

std::vector<std::string> listing(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir))
        names.push_back(entry.path().filename().string());
    return names;
}

// The key is the FNV-1a 128 of the byte stream docs/cache.md lists, checked against an
// independent Python implementation of that list (struct.pack('<Q' / '<d') and the FNV loop),
// at format version 6.
TEST(FormFactorCacheKey, MatchesTheDocumentedByteStream) {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {{0, 1, 2}};
    mesh.materials = {0};
    const PatchMesh patches = verify::patchesOf(mesh);
    FormFactorSettings k16;  // the Python oracle was computed with K = 16 (the default was then)
    k16.raysPerPair = 16;
    EXPECT_EQ(formFactorKey(patches, k16, "cpu").hex(), "07bcdca4c34e9d88974d55faa3c8bd92");
    FormFactorSettings stochastic;
    stochastic.method = FormFactorMethod::Stochastic;
    stochastic.quadratureLevel = 2;
    stochastic.raysPerPair = 0;
    stochastic.seed = 7;
    stochastic.shaftCulling = false;
    stochastic.stochasticRays = 512;
    EXPECT_EQ(formFactorKey(patches, stochastic, "kernel").hex(),
              "c7f84c366beb7226cb3aeacb3117d195");
}

TEST(FormFactorCacheKey, ChangesWithEverythingFDependsOn) {
    const PatchMesh& patches = built().patches;
    const FormFactorSettings base = built().settings;
    const FormFactorKey key = formFactorKey(patches, base, "cpu");
    EXPECT_EQ(formFactorKey(patches, base, "cpu"), key);  // deterministic

    PatchMesh moved = patches;
    Vec3d& vertex = moved.positions[moved.patches.back()[2]];
    vertex.z = std::nextafter(vertex.z, 2.0);  // one ulp
    EXPECT_NE(formFactorKey(moved, base, "cpu"), key);

    PatchMesh reordered = patches;
    std::swap(reordered.patches[0], reordered.patches[1]);
    EXPECT_NE(formFactorKey(reordered, base, "cpu"), key);

    PatchMesh fewer = patches;
    fewer.patches.pop_back();
    EXPECT_NE(formFactorKey(fewer, base, "cpu"), key);

    const auto changed = [&](auto edit) {
        FormFactorSettings settings = base;
        edit(settings);
        return formFactorKey(patches, settings, "cpu");
    };
    EXPECT_NE(changed([](auto& s) { s.method = FormFactorMethod::Riemann; }), key);
    EXPECT_NE(changed([](auto& s) { s.method = FormFactorMethod::Nusselt; }), key);
    EXPECT_NE(changed([](auto& s) { s.quadratureLevel = 2; }), key);
    EXPECT_NE(changed([](auto& s) { s.raysPerPair = 17; }), key);
    EXPECT_NE(changed([](auto& s) { s.seed = 2; }), key);
    EXPECT_NE(changed([](auto& s) { s.shaftCulling = false; }), key);
    EXPECT_NE(formFactorKey(patches, base, "kernel"), key);

    FormFactorSettings stochastic = base;
    stochastic.method = FormFactorMethod::Stochastic;
    FormFactorSettings moreRays = stochastic;
    moreRays.stochasticRays *= 2;
    EXPECT_NE(formFactorKey(patches, moreRays, "cpu"), formFactorKey(patches, stochastic, "cpu"));
}

TEST(FormFactorCacheKey, IgnoresWhatFDoesNotDependOn) {
    const PatchMesh& patches = built().patches;
    const FormFactorSettings base = built().settings;
    const FormFactorKey key = formFactorKey(patches, base, "cpu");

    PatchMesh repainted = patches;
    for (uint32_t& material : repainted.materials)
        material += 1;
    EXPECT_EQ(formFactorKey(repainted, base, "cpu"), key);

    const auto changed = [&](auto edit) {
        FormFactorSettings settings = base;
        edit(settings);
        return formFactorKey(patches, settings, "cpu");
    };
    EXPECT_EQ(changed([](auto& s) { s.threads = 3; }), key);
    EXPECT_EQ(changed([](auto& s) { s.maxMemoryBytes = 12345; }), key);
    EXPECT_EQ(changed([](auto& s) { s.progress = !s.progress; }), key);
    EXPECT_EQ(changed([](auto& s) { s.stochasticRays = 7; }), key);  // method is hybrid
}

// F round trips bit for bit: the arrays and the stats' bytes are identical after store + load.
TEST(FormFactorCache, RoundTripIsBitExact) {
    const fs::path dir = test::testTempDir() / "cache";
    const FormFactorCache cache(dir);
    const FormFactorKey key = builtKey();
    const SparseMatrix& f = built().result.matrix;
    ASSERT_GT(f.nonzeroCount(), 1000u);
    EXPECT_EQ(cache.load(key).status, CacheLookup::Status::Miss);
    EXPECT_FALSE(cache.contains(key));

    EXPECT_EQ(cache.store(key, f, built().result.stats), "");
    EXPECT_TRUE(cache.contains(key));
    EXPECT_EQ(listing(dir), std::vector<std::string>{key.hex() + ".dff"});  // no temp files
    EXPECT_EQ(cache.entryPath(key), dir / (key.hex() + ".dff"));

    const CacheLookup hit = cache.load(key);
    ASSERT_EQ(hit.status, CacheLookup::Status::Hit) << hit.message;
    EXPECT_EQ(hit.matrix.size, f.size);
    EXPECT_EQ(hit.matrix.rowOffsets, f.rowOffsets);
    EXPECT_EQ(hit.matrix.columns, f.columns);
    ASSERT_EQ(hit.matrix.values.size(), f.values.size());
    EXPECT_EQ(std::memcmp(hit.matrix.values.data(), f.values.data(), f.values.size() * 4), 0);
    EXPECT_EQ(std::memcmp(&hit.stats, &built().result.stats, sizeof(FormFactorStats)), 0);

    // File size as documented: 64-byte header, stats, 8 (n + 1) + 8 nnz.
    EXPECT_EQ(fs::file_size(cache.entryPath(key)),
              64 + sizeof(FormFactorStats) + 8 * (f.size + 1) + 8 * f.nonzeroCount());
    // A second store (after a rebuild) replaces the entry.
    EXPECT_EQ(cache.store(key, f, built().result.stats), "");
    EXPECT_EQ(cache.load(key).status, CacheLookup::Status::Hit);
    EXPECT_EQ(listing(dir).size(), 1u);
}

TEST(FormFactorCache, EmptyMatrixRoundTrips) {
    const FormFactorCache cache(test::testTempDir());
    const FormFactorKey key{1, 2};
    FormFactorStats stats;
    stats.patches = 5;
    EXPECT_EQ(cache.store(key, SparseMatrix::zeros(5), stats), "");
    const CacheLookup hit = cache.load(key);
    ASSERT_EQ(hit.status, CacheLookup::Status::Hit) << hit.message;
    EXPECT_EQ(hit.matrix.size, 5u);
    EXPECT_EQ(hit.matrix.nonzeroCount(), 0u);
    EXPECT_EQ(hit.stats.patches, 5u);
}

// Each damaged entry is Rejected with a one-line message naming the file and the fault, and
// removed; the next store rebuilds it.
class FormFactorCacheCorruption : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = test::testTempDir();
        ASSERT_EQ(cache().store(builtKey(), built().result.matrix, built().result.stats), "");
        path_ = cache().entryPath(builtKey());
        bytes_ = readBytes(path_);
        ASSERT_GT(bytes_.size(), 1000u);
    }
    FormFactorCache cache() const { return FormFactorCache(dir_); }

    // Loads `bytes` as the entry and expects a rejection mentioning `fault`, the file removed.
    void expectRejected(const std::string& bytes, const std::string& fault,
                        uint64_t maxMemoryBytes = 0, std::optional<FormFactorKey> key = {}) {
        writeBytes(path_, bytes);
        const CacheLookup lookup = cache().load(key.value_or(builtKey()), maxMemoryBytes);
        EXPECT_EQ(lookup.status, CacheLookup::Status::Rejected);
        EXPECT_EQ(lookup.message.rfind(path_.string() + ": ", 0), 0u) << lookup.message;
        EXPECT_NE(lookup.message.find(fault), std::string::npos) << lookup.message;
        EXPECT_EQ(lookup.message.find('\n'), std::string::npos) << lookup.message;
        EXPECT_TRUE(lookup.matrix.values.empty());
        EXPECT_FALSE(fs::exists(path_)) << "a rejected entry stays: " << lookup.message;
        // Rebuilt: storing again gives a valid entry.
        EXPECT_EQ(cache().store(builtKey(), built().result.matrix, built().result.stats), "");
        EXPECT_EQ(cache().load(builtKey()).status, CacheLookup::Status::Hit);
    }

    fs::path dir_, path_;
    std::string bytes_;
};

TEST_F(FormFactorCacheCorruption, FlippedPayloadByte) {
    for (std::size_t offset : {std::size_t{64}, std::size_t{64 + sizeof(FormFactorStats) + 3},
                               bytes_.size() / 2, bytes_.size() - 1}) {
        std::string bytes = bytes_;
        bytes[offset] ^= 0x10;
        expectRejected(bytes, "payload checksum mismatch (file corrupt); rebuilding");
    }
}

TEST_F(FormFactorCacheCorruption, FlippedHeaderByte) {
    for (std::size_t offset : {12, 20, 33, 41, 50, 60}) {
        std::string bytes = bytes_;
        bytes[offset] ^= 0x01;
        expectRejected(bytes, "header checksum mismatch (file corrupt)");
    }
    std::string magic = bytes_;
    magic[0] = 'X';
    expectRejected(magic, "not a DaisyRiot form-factor cache file (bad magic)");
}

TEST_F(FormFactorCacheCorruption, Truncated) {
    expectRejected(bytes_.substr(0, bytes_.size() - 1), "(truncated or damaged)");
    expectRejected(bytes_.substr(0, 100), "(truncated or damaged)");
    expectRejected(bytes_.substr(0, 63), "truncated header (63 of 64 bytes)");
    expectRejected(bytes_ + "extra", "(truncated or damaged)");
}

TEST_F(FormFactorCacheCorruption, EmptyFile) {
    expectRejected("", "empty file");
}

TEST_F(FormFactorCacheCorruption, WrongVersion) {
    std::string bytes = bytes_;
    put<uint32_t>(bytes, 8, kFormFactorCacheVersion + 1);
    reseal(bytes);
    expectRejected(bytes,
                   "format version " + std::to_string(kFormFactorCacheVersion + 1) +
                       ", this build reads version " + std::to_string(kFormFactorCacheVersion));
}

// An entry renamed (or copied) to another key's file name.
TEST_F(FormFactorCacheCorruption, WrongKey) {
    const FormFactorKey other{builtKey().hi ^ 1, builtKey().lo};
    const fs::path otherPath = cache().entryPath(other);
    fs::rename(path_, otherPath);
    EXPECT_FALSE(cache().contains(other));
    const CacheLookup lookup = cache().load(other);
    EXPECT_EQ(lookup.status, CacheLookup::Status::Rejected);
    EXPECT_EQ(lookup.message,
              otherPath.string() + ": holds the entry for key " + builtKey().hex() + ", not " +
                  other.hex() + " (renamed or copied file); rebuilding");
    EXPECT_FALSE(fs::exists(otherPath));
}

// A forged header (valid checksum) whose CSR arrays are out of order: the structure check is the
// last line of defence.
TEST_F(FormFactorCacheCorruption, InvalidStructureWithValidChecksums) {
    std::string bytes = bytes_;
    const std::size_t columns = 64 + sizeof(FormFactorStats) + 8 * (built().result.matrix.size + 1);
    put<uint32_t>(bytes, columns, UINT32_MAX);  // row 0's first column, out of range
    reseal(bytes);
    expectRejected(bytes, "invalid matrix: row 0: column 4294967295 >= size");
}

// A header claiming a huge matrix: refused before any allocation, by the memory limit when one
// is given, else by the file size; and a claim of more than n^2 non-zeros.
TEST_F(FormFactorCacheCorruption, HugeSizesAreRefusedWithoutAllocating) {
    std::string bytes = bytes_;
    put<uint64_t>(bytes, 32, uint64_t{1} << 31);  // patches
    put<uint64_t>(bytes, 40, uint64_t{1} << 40);  // non-zeros: 8 TiB of CSR
    reseal(bytes);
    expectRejected(bytes, "non-zeros) needs 8.02 TiB, over the memory limit of 1.00 GiB",
                   uint64_t{1} << 30);
    expectRejected(bytes, "(truncated or damaged)");

    std::string squared = bytes_;
    put<uint64_t>(squared, 40,
                  uint64_t{built().result.matrix.size} * built().result.matrix.size + 1);
    reseal(squared);
    expectRejected(squared, "more than n^2 (file corrupt)");
}

// A valid entry over the memory limit is refused but kept: it is not corrupt.
TEST_F(FormFactorCacheCorruption, ValidEntryOverTheMemoryLimitIsKept) {
    const CacheLookup lookup = cache().load(builtKey(), 1000);
    EXPECT_EQ(lookup.status, CacheLookup::Status::Rejected);
    EXPECT_NE(lookup.message.find("over the memory limit of 1000 B"), std::string::npos)
        << lookup.message;
    EXPECT_TRUE(fs::exists(path_));
    EXPECT_EQ(cache().load(builtKey()).status, CacheLookup::Status::Hit);
}

// Storing where the folder cannot be created (its parent is a regular file: fails even as root)
// is a warning, not an error or exception, and leaves nothing behind.
TEST(FormFactorCache, UncreatableFolderGivesAWarning) {
    const fs::path dir = test::testTempDir();
    test::writeFile(dir, "file", "not a folder");
    const fs::path folder = dir / "file" / "cache";
    const FormFactorCache cache(folder);
    std::string warning;
    EXPECT_NO_THROW(warning = cache.store(builtKey(), built().result.matrix, built().result.stats));
    EXPECT_NE(warning.find(folder.string()), std::string::npos) << warning;
    EXPECT_NE(warning.find("Not a directory"), std::string::npos) << warning;
    EXPECT_EQ(warning.find('\n'), std::string::npos);
    EXPECT_EQ(listing(dir), std::vector<std::string>{"file"});
    EXPECT_EQ(cache.load(builtKey()).status, CacheLookup::Status::Miss);
    EXPECT_FALSE(cache.contains(builtKey()));
}

// A read-only folder (chmod 0500). Root ignores permissions, so this one skips there; the test
// above covers the failure path for root too.
TEST(FormFactorCache, ReadOnlyFolderGivesAWarning) {
    if (geteuid() == 0) GTEST_SKIP() << "running as root: chmod 0500 does not stop root's writes";
    const fs::path dir = test::testTempDir();
    ASSERT_EQ(chmod(dir.c_str(), 0500), 0);
    const FormFactorCache cache(dir);
    std::string warning;
    EXPECT_NO_THROW(warning = cache.store(builtKey(), built().result.matrix, built().result.stats));
    chmod(dir.c_str(), 0700);
    EXPECT_NE(warning.find(dir.string()), std::string::npos) << warning;
    EXPECT_NE(warning.find("Permission denied"), std::string::npos) << warning;
    EXPECT_TRUE(listing(dir).empty());
}

TEST(FormFactorCache, DefaultDirectoryFollowsXdg) {
    const auto saved = [](const char* name) -> std::optional<std::string> {
        const char* value = std::getenv(name);
        return value ? std::optional<std::string>(value) : std::nullopt;
    };
    const auto restore = [](const char* name, const std::optional<std::string>& value) {
        if (value) {
            setenv(name, value->c_str(), 1);
        } else {
            unsetenv(name);
        }
    };
    const auto xdg = saved("XDG_CACHE_HOME"), home = saved("HOME");
    setenv("HOME", "/home/someone", 1);
    setenv("XDG_CACHE_HOME", "/var/cache/me", 1);
    EXPECT_EQ(FormFactorCache::defaultDirectory(), fs::path("/var/cache/me/daisyriot"));
    setenv("XDG_CACHE_HOME", "relative/cache", 1);  // XDG Base Directory spec: ignore relative
    EXPECT_EQ(FormFactorCache::defaultDirectory(), fs::path("/home/someone/.cache/daisyriot"));
    unsetenv("XDG_CACHE_HOME");
    EXPECT_EQ(FormFactorCache::defaultDirectory(), fs::path("/home/someone/.cache/daisyriot"));
    unsetenv("HOME");
    EXPECT_EQ(FormFactorCache::defaultDirectory(), fs::path());
    restore("XDG_CACHE_HOME", xdg);
    restore("HOME", home);
}

// The size limit (docs/cache.md, "Size limit and eviction"): after a store, the least recently
// used other entries go until the folder is under the limit, and a hit counts as a use.
TEST(FormFactorCacheLimit, StoreEvictsTheLeastRecentlyUsed) {
    const fs::path dir = test::testTempDir();
    const SparseMatrix f = SparseMatrix::zeros(50);
    FormFactorStats stats;
    const uint64_t entryBytes = 64 + sizeof(FormFactorStats) + 8 * 51;
    const FormFactorCache cache(dir, 3 * entryBytes);
    EXPECT_EQ(cache.sizeLimitBytes(), 3 * entryBytes);
    const FormFactorKey a{1, 1}, b{2, 2}, c{3, 3}, d{4, 4};
    int hoursAgo = 3;
    for (const FormFactorKey& key : {a, b, c}) {
        ASSERT_EQ(cache.store(key, f, stats), "");
        ASSERT_EQ(fs::file_size(cache.entryPath(key)), entryBytes);
        fs::last_write_time(cache.entryPath(key),
                            fs::file_time_type::clock::now() - std::chrono::hours(hoursAgo--));
    }
    // a was written first, but its hit makes b the least recently used.
    ASSERT_EQ(cache.load(a).status, CacheLookup::Status::Hit);
    EXPECT_EQ(cache.store(d, f, stats), "");
    EXPECT_FALSE(fs::exists(cache.entryPath(b)));
    for (const FormFactorKey& key : {a, c, d})
        EXPECT_TRUE(fs::exists(cache.entryPath(key))) << key.hex();
}

// An entry larger than the whole limit is not written (one line says so), and nothing is
// evicted for it.
TEST(FormFactorCacheLimit, EntryOverTheLimitIsNotStored) {
    const fs::path dir = test::testTempDir();
    FormFactorStats stats;
    ASSERT_EQ(FormFactorCache(dir).store({1, 1}, SparseMatrix::zeros(50), stats), "");
    const FormFactorCache small(dir, 100);
    const std::string message = small.store({2, 2}, SparseMatrix::zeros(50), stats);
    EXPECT_NE(message.find("F not cached: its entry of "), std::string::npos) << message;
    EXPECT_NE(message.find("over the cache size limit of 100 B (--cache-size)"), std::string::npos)
        << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
    const std::string kept = FormFactorKey{1, 1}.hex() + ".dff";
    EXPECT_EQ(listing(dir), std::vector<std::string>{kept});
    EXPECT_EQ(describeEntry(dir / kept), "F: 50 patches, 0 non-zeros");
}

// The benchmark scene (7,712 patches, docs/performance.md) and a ~1e5-patch room: the key
// covers the last vertex; its time is logged, not asserted.
TEST(FormFactorCacheKey, LargeMeshes) {
    auto scene = loadScene(test::assetPath("scenes/blacklight_box.gltf"));
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    PatchMesh box = std::move(buildPatchMesh(scene->mesh, 0).value());
    PatchMesh room = verify::patchesOf(verify::unitCubeRoom(91));
    ASSERT_EQ(box.patchCount(), 7712u);
    ASSERT_EQ(room.patchCount(), 99372u);  // 6 faces x 91^2 quads x 2
    for (PatchMesh* mesh : {&box, &room}) {
        const auto start = std::chrono::steady_clock::now();
        const FormFactorKey key = formFactorKey(*mesh, {}, "cpu");
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
        std::cout << "formFactorKey: " << mesh->patchCount() << " patches in " << ms << " ms\n";
        Vec3d& last = mesh->positions[mesh->patches.back()[2]];
        last.x = std::nextafter(last.x, 1e300);
        EXPECT_NE(formFactorKey(*mesh, {}, "cpu"), key);
    }
}

}  // namespace
}  // namespace daisy
