// docs/errors.md, row by row: each row names a bad input, the exact line daisy prints
// and its exit status. The rows are read from the document itself, and every row's id must have
// a case below that builds the input and gives the command, so the catalogue and the program
// cannot drift apart. Inputs are variants of tests/data/gltf/lamp_room.gltf (a floor and a UV
// lamp, two materials, one camera) or small OBJ files. `<dir>` in a message is the test's
// temporary folder.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "image/image_io.h"
#include "test_util.h"

namespace daisy::test {
namespace {

using nlohmann::json;

json lampRoom() {
    std::ifstream in(testDataPath("gltf/lamp_room.gltf"));
    return json::parse(in);
}

json& spectral(json& room, int material) {
    return room["materials"][material]["extensions"]["DAISY_materials_spectral"];
}

// A copy of lamp_room with its buffer uris as written (data: uris), saved as dir/name.
std::string saveGltf(const std::filesystem::path& dir, const std::string& name, const json& doc) {
    return writeFile(dir, name, doc.dump());
}

std::string wrapScale(json room, double scale) {
    room["nodes"].push_back(
        {{"scale", {scale, scale, scale}}, {"children", room["scenes"][0]["nodes"]}});
    room["scenes"][0]["nodes"] = {room["nodes"].size() - 1};
    return room.dump();
}

// The GLB of lamp_room: its one data: buffer as the BIN chunk.
std::string lampRoomGlb() {
    json room = lampRoom();
    std::string uri = room["buffers"][0]["uri"];
    const std::string base64 = uri.substr(uri.find(',') + 1);
    std::string bin;
    int bits = 0, value = 0;
    for (char c : base64) {
        const std::string alphabet =
            "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        const auto at = alphabet.find(c);
        if (at == std::string::npos) break;
        value = (value << 6) | int(at);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            bin += char((value >> bits) & 0xFF);
        }
    }
    room["buffers"][0].erase("uri");
    std::string text = room.dump();
    while (text.size() % 4)
        text += ' ';
    while (bin.size() % 4)
        bin += '\0';
    auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    const std::string chunks =
        u32(uint32_t(text.size())) + "JSON" + text + u32(uint32_t(bin.size())) + "BIN" + '\0' + bin;
    return "glTF" + u32(2) + u32(uint32_t(12 + chunks.size())) + chunks;
}

std::string replaceU32(std::string bytes, std::size_t offset, uint32_t value) {
    bytes.replace(offset, 4, std::string(reinterpret_cast<const char*>(&value), 4));
    return bytes;
}

// lamp_room with a 5 cd point light in the middle of the room (KHR_lights_punctual).
json withPointLight(json room) {
    room["extensionsUsed"].push_back("KHR_lights_punctual");
    room["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 5}}};
    room["nodes"].push_back({{"translation", {0.25, 0.25, 0.25}},
                             {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    room["nodes"][0]["children"].push_back(room["nodes"].size() - 1);
    return room;
}

// lamp_room with the floor's base colour read from the image at `uri`.
json withTexture(json room, const std::string& uri) {
    room["images"] = {{{"uri", uri}}};
    room["textures"] = {{{"source", 0}}};
    room["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    return room;
}

// The PNG signature and an IHDR chunk of a width x height 8-bit RGB image (CRC not checked).
std::string pngHeader(uint32_t width, uint32_t height) {
    const auto be32 = [](uint32_t v) {
        return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
    };
    return std::string("\x89PNG\r\n\x1a\n", 8) + be32(13) + "IHDR" + be32(width) + be32(height) +
        std::string("\x08\x02\x00\x00\x00", 5) + be32(0);
}

// Builds the input of a row in `dir` and returns the daisy arguments.
using Case = std::function<std::string(const std::filesystem::path&)>;

std::string info(const std::string& path, const std::string& extra = "") {
    return "info " + path + extra;
}

const std::map<std::string, Case>& cases() {
    static const std::map<std::string, Case> table = {
        {"gltf-deep-extras",
         [](const auto& dir) {
             std::string text = lampRoom().dump();
             text.insert(1,
                         "\"extras\":" + std::string(15000, '[') + std::string(15000, ']') + ",");
             return info(writeFile(dir, "deep.gltf", text));
         }},
        {"gltf-version-1",
         [](const auto& dir) {
             json room = lampRoom();
             room["asset"]["version"] = "1.0";
             return info(saveGltf(dir, "v1.gltf", room));
         }},
        {"gltf-version-3",
         [](const auto& dir) {
             json room = lampRoom();
             room["asset"]["version"] = "3.0";
             return info(saveGltf(dir, "v3.gltf", room));
         }},
        {"gltf-min-version",
         [](const auto& dir) {
             json room = lampRoom();
             room["asset"]["minVersion"] = "2.5";
             return info(saveGltf(dir, "min.gltf", room));
         }},
        {"gltf-reflectance-2^32",
         [](const auto& dir) {
             json room = lampRoom();
             spectral(room, 0)["reflectance"] = {{"wavelengths", {400, 500, 600}},
                                                 {"values", {0.5, 4294967296ull, 0.5}}};
             return info(saveGltf(dir, "big.gltf", room));
         }},
        {"gltf-emission-negative-2^32",
         [](const auto& dir) {
             json room = lampRoom();
             spectral(room, 1)["emission"] = {{"wavelengths", {350, 400}},
                                              {"values", {-4294967295ll, 1}}};
             return info(saveGltf(dir, "neg.gltf", room));
         }},
        {"gltf-fluorescence-column",
         [](const auto& dir) {
             json room = lampRoom();
             spectral(room, 0)["fluorescence"] = {
                 {"matrix",
                  {{"wavelengths", {400, 500}},
                   {"values", {{0.5, 0}, {4294967296ull + 4294967296ull, 0.5}}}}}};
             return info(saveGltf(dir, "column.gltf", room));
         }},
        {"gltf-wavelength-2^32",
         [](const auto& dir) {
             json room = lampRoom();
             spectral(room, 0)["reflectance"] = {{"wavelengths", {400, 4294967696ull}},
                                                 {"values", {0.5, 0.5}}};
             return info(saveGltf(dir, "nm.gltf", room));
         }},
        {"gltf-null-value",
         [](const auto& dir) {
             json room = lampRoom();
             spectral(room, 0)["reflectance"] = {{"wavelengths", {400, 500, 600}},
                                                 {"values", {0.5, nullptr, 0.5, 0.5}}};
             return info(saveGltf(dir, "null.gltf", room));
         }},
        {"gltf-empty-fluorescence",
         [](const auto& dir) {
             json room = lampRoom();
             spectral(room, 0)["fluorescence"] = json::object();
             return info(saveGltf(dir, "empty.gltf", room));
         }},
        {"materials-reflectance-2^32",
         [](const auto& dir) {
             const std::string materials = writeFile(
                 dir, "m.json",
                 R"({"floor": {"reflectance": {"wavelengths": [400, 500, 600], "values": [0.5, 4294967296, 0.5]}}})");
             return info(testDataPath("gltf/lamp_room.gltf"), " --materials " + materials);
         }},
        {"materials-not-a-file",
         [](const auto&) {
             return info(testDataPath("gltf/lamp_room.gltf"), " --materials /dev/zero");
         }},
        {"gltf-emissive-strength-1e308",
         [](const auto& dir) {
             json room = lampRoom();
             room["materials"][1]["extensions"].erase("DAISY_materials_spectral");
             room["materials"][1]["extensions"]["KHR_materials_emissive_strength"] = {
                 {"emissiveStrength", 1e308}};
             return info(saveGltf(dir, "strong.gltf", room));
         }},
        {"gltf-no-emitter",
         [](const auto& dir) {
             json room = lampRoom();
             room["materials"][1].erase("emissiveFactor");
             room["materials"][1].erase("extensions");
             return info(saveGltf(dir, "dark.gltf", room));
         }},
        {"gltf-draco-undecodable",
         [](const auto& dir) {
             // The Draco Cornell box (tests/data/blender, tools/make_draco_fixture.py) with its
             // compressed buffer zeroed.
             std::ifstream in(testDataPath("blender/cornell_draco.gltf"));
             const json box = json::parse(in);
             writeFile(dir, "cornell_draco.bin",
                       std::string(box["buffers"][0]["byteLength"].get<std::size_t>(), '\0'));
             return info(saveGltf(dir, "draco.gltf", box));
         }},
        {"gltf-missing-texture",
         [](const auto& dir) {
             return info(saveGltf(dir, "texture.gltf", withTexture(lampRoom(), "missing.png")));
         }},
        {"gltf-scale-1e12",
         [](const auto& dir) {
             return info(writeFile(dir, "huge.gltf", wrapScale(lampRoom(), 1e12)));
         }},
        {"gltf-scale-1e-12",
         [](const auto& dir) {
             return info(writeFile(dir, "tiny.gltf", wrapScale(lampRoom(), 1e-12)));
         }},
        {"gltf-camera-1e18",
         [](const auto& dir) {
             json room = lampRoom();
             room["nodes"][3]["translation"] = {1e18, 0, 0};
             return info(saveGltf(dir, "camera.gltf", room));
         }},
        {"gltf-node-1e17",
         [](const auto& dir) {
             json room = lampRoom();
             room["nodes"][2]["translation"] = {0, 1e17, 0};
             return info(saveGltf(dir, "far.gltf", room));
         }},
        {"materials-name-newline",
         [](const auto& dir) {
             const std::string materials = writeFile(
                 dir, "m.json",
                 R"({"flo\nor\nerror: fake": {"reflectance": {"wavelengths": [400, 700], "values": [0.5, 0.5]}}})");
             return info(saveGltf(dir, "room.gltf", lampRoom()), " --materials " + materials);
         }},
        {"materials-duplicate-key",
         [](const auto& dir) {
             const std::string materials = writeFile(
                 dir, "m.json",
                 R"({"floor": {"reflectance": {"wavelengths": [400, 700], "values": [0.5, 0.5]}},)"
                 R"( "floor": {"reflectance": {"wavelengths": [400, 700], "values": [0.2, 0.2]}}})");
             return info(testDataPath("gltf/lamp_room.gltf"), " --materials " + materials);
         }},
        {"gltf-light-range-0",
         [](const auto& dir) {
             json room = withPointLight(lampRoom());
             room["extensions"]["KHR_lights_punctual"]["lights"][0]["range"] = 0;
             return info(saveGltf(dir, "range.gltf", room));
         }},
        {"gltf-spot-without-spot",
         [](const auto& dir) {
             json room = withPointLight(lampRoom());
             room["extensions"]["KHR_lights_punctual"]["lights"][0]["type"] = "spot";
             return info(saveGltf(dir, "spot.gltf", room));
         }},
        {"gltf-texcoord-1-missing",
         [](const auto& dir) {
             const std::vector<uint8_t> grey(2 * 2 * 3, 128);
             EXPECT_TRUE(writePng((dir / "grey.png").string(), 2, 2, grey));
             json room = withTexture(lampRoom(), "grey.png");
             room["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1;
             return info(saveGltf(dir, "uv.gltf", room));
         }},
        {"gltf-image-empty",
         [](const auto& dir) {
             writeFile(dir, "empty.png", "");
             return info(saveGltf(dir, "texture.gltf", withTexture(lampRoom(), "empty.png")));
         }},
        {"gltf-image-truncated-jpeg",
         [](const auto& dir) {
             writeFile(dir, "cut.jpg",
                       std::string("\xff\xd8\xff\xe0\x00\x10JFIF", 10) + std::string(21, '\0'));
             return info(saveGltf(dir, "texture.gltf", withTexture(lampRoom(), "cut.jpg")));
         }},
        {"gltf-image-png-too-large",
         [](const auto& dir) {
             writeFile(dir, "huge.png", pngHeader(20000, 20000));
             return info(saveGltf(dir, "texture.gltf", withTexture(lampRoom(), "huge.png")));
         }},
        {"gltf-jpeg-huffman-over-256",
         [](const auto& dir) {
             // SOI, then a DHT segment (length 2 + 17 + 300) whose AC table lists 255 + 45
             // codes; its class/id byte is byte 6.
             std::string counts(16, '\0');
             counts[0] = char(255);
             counts[15] = char(45);
             writeFile(dir, "huffman.jpg",
                       std::string("\xFF\xD8\xFF\xC4\x01\x3F\x10", 7) + counts +
                           std::string(300, '\0') + "\xFF\xD9");
             return info(saveGltf(dir, "texture.gltf", withTexture(lampRoom(), "huffman.jpg")));
         }},
        {"gltf-image-base64",
         [](const auto& dir) {
             return info(saveGltf(dir, "texture.gltf",
                                  withTexture(lampRoom(), "data:image/png;base64,@@@@")));
         }},
        {"transport-hierarchical-reference",
         [](const auto& dir) {
             return "solve " + saveGltf(dir, "room.gltf", lampRoom()) +
                 " --transport hierarchical --backend reference --no-cache";
         }},
        {"transport-hierarchical-formfactors",
         [](const auto& dir) {
             return "formfactors " + saveGltf(dir, "room.gltf", lampRoom()) +
                 " --transport hierarchical --no-cache -o " + (dir / "F.mtx").string();
         }},
        {"bench-stress-unwritable-output",
         [](const auto& dir) {
             return "bench --stress --quick -o " + (dir / "missing" / "stress.csv").string();
         }},
        {"gltf-buffer-uri-dot",
         [](const auto& dir) {
             json room = lampRoom();
             room["buffers"][0]["uri"] = ".";
             return info(saveGltf(dir, "dot.gltf", room));
         }},
        {"gltf-accessor-count-2^32-1",
         [](const auto& dir) {
             json room = lampRoom();
             room["accessors"][0] = {
                 {"componentType", 5126}, {"count", 4294967295ull}, {"type", "VEC3"}};
             return info(saveGltf(dir, "count.gltf", room), " --max-memory 1G");
         }},
        {"gltf-sparse-max-memory",
         [](const auto& dir) {
             json room = lampRoom();
             room["accessors"][0] = {{"componentType", 5126},
                                     {"count", 30000000},
                                     {"type", "VEC3"},
                                     {"sparse",
                                      {{"count", 1},
                                       {"indices", {{"bufferView", 1}, {"componentType", 5123}}},
                                       {"values", {{"bufferView", 0}}}}}};
             return info(saveGltf(dir, "sparse.gltf", room), " --max-memory 1M");
         }},
        {"glb-chunk-length",
         [](const auto& dir) {
             return info(writeFile(dir, "chunk.glb", replaceU32(lampRoomGlb(), 12, 1u << 30)));
         }},
        {"glb-total-length",
         [](const auto& dir) {
             return info(writeFile(dir, "length.glb", replaceU32(lampRoomGlb(), 8, 99)));
         }},
        {"glb-truncated",
         [](const auto& dir) {
             const std::string glb = lampRoomGlb();
             return info(writeFile(dir, "cut.glb", replaceU32(glb.substr(0, 30), 8, 30)));
         }},
        {"obj-nan",
         [](const auto& dir) {
             return info(writeFile(dir, "nan.obj", "v 0 0 0\nv nan 1 0\nv 0 1 0\nf 1 2 3\n"));
         }},
        {"obj-word",
         [](const auto& dir) {
             return info(writeFile(dir, "word.obj", "v 0 0 0\nv 1 0 0\nv hello 1 0\nf 1 2 3\n"));
         }},
        {"tolerance-0",
         [](const auto&) {
             return "solve " + testDataPath("gltf/lamp_room.gltf") + " --tolerance 0";
         }},
        {"validate-rtol-nan",
         [](const auto&) {
             return "validate " + testDataPath("gltf/lamp_room.gltf") +
                 " --backend vulkan --rtol nan";
         }},
        {"render-near-radius-nan",
         [](const auto& dir) {
             return "render " + testDataPath("gltf/lamp_room.gltf") + " --near-radius nan -o " +
                 (dir / "out.png").string();
         }},
        {"subdivide-nan",
         [](const auto&) {
             return "info " + testDataPath("gltf/lamp_room.gltf") + " --subdivide nan";
         }},
        {"vulkan-rays-unknown",
         [](const auto&) {
             return "formfactors " + testDataPath("gltf/lamp_room.gltf") +
                 " --backend vulkan --vulkan-rays fast";
         }},
        {"seed-negative",
         [](const auto&) { return "solve " + testDataPath("gltf/lamp_room.gltf") + " --seed -1"; }},
        {"seed-2^64",
         [](const auto&) {
             return "solve " + testDataPath("gltf/lamp_room.gltf") + " --seed 18446744073709551616";
         }},
        {"render-unwritable-output",
         [](const auto& dir) {
             return "render " + testDataPath("gltf/lamp_room.gltf") + " -o " +
                 (dir / "missing" / "out.png").string();
         }},
        {"formfactors-output-is-folder",
         [](const auto& dir) {
             return "formfactors " + testDataPath("gltf/lamp_room.gltf") + " -o " + dir.string();
         }},
        {"render-image-max-memory",
         [](const auto& dir) {
             return "render " + saveGltf(dir, "room.gltf", lampRoom()) +
                 " --width 16384 --height 16384 --max-memory 1G -o " + (dir / "big.png").string();
         }},
    };
    return table;
}

struct Row {
    std::string id, message;
    int status = -1;
};

// The rows of docs/errors.md's catalogue: "| `id` | input | `message` | status |".
std::vector<Row> catalogueRows() {
    std::ifstream in(std::string(DAISY_DOCS_DIR) + "/errors.md");
    std::vector<Row> rows;
    std::string line;
    while (std::getline(in, line)) {
        if (!line.starts_with("| `")) continue;
        std::vector<std::string> cells;
        std::stringstream stream(line.substr(1));
        std::string cell;
        while (std::getline(stream, cell, '|')) {
            const auto first = cell.find_first_not_of(' ');
            const auto last = cell.find_last_not_of(' ');
            cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
        }
        if (cells.size() < 4) continue;
        auto unquote = [](std::string text) {
            if (text.size() >= 2 && text.front() == '`' && text.back() == '`') {
                text = text.substr(1, text.size() - 2);
            }
            return text;
        };
        rows.push_back({unquote(cells[0]), unquote(cells[2]), std::stoi(cells[3])});
    }
    return rows;
}

std::string replaceAll(std::string text, const std::string& from, const std::string& to) {
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at)) {
        text.replace(at, from.size(), to);
        at += to.size();
    }
    return text;
}

TEST(ErrorsCatalogue, EveryRowHasACaseAndEveryCaseARow) {
    const std::vector<Row> rows = catalogueRows();
    ASSERT_GE(rows.size(), cases().size()) << "docs/errors.md has too few rows";
    std::map<std::string, int> seen;
    for (const Row& row : rows) {
        EXPECT_TRUE(cases().count(row.id)) << "no test case for docs/errors.md row " << row.id;
        seen[row.id]++;
    }
    for (const auto& [id, make] : cases()) {
        EXPECT_EQ(seen[id], 1) << "case " << id << " should appear once in docs/errors.md";
    }
}

// Each row: the command prints the row's message as one whole line and exits with its status;
// nothing is left behind in the folder but the inputs.
TEST(ErrorsCatalogue, EachRowGivesItsMessageAndStatus) {
    for (const Row& row : catalogueRows()) {
        const auto found = cases().find(row.id);
        if (found == cases().end()) continue;
        SCOPED_TRACE(row.id);
        const auto dir = testTempDir() / row.id;
        std::filesystem::create_directories(dir);
        const std::string arguments = found->second(dir);
        const std::string expected = replaceAll(row.message, "<dir>", dir.string());
        const RunResult run = runDaisy(arguments);
        EXPECT_EQ(run.status, row.status) << run.output;
        EXPECT_NE(("\n" + run.output).find("\n" + expected + "\n"), std::string::npos)
            << "expected the line\n  " << expected << "\ngot\n"
            << run.output;
        for (const auto& entry : std::filesystem::directory_iterator(dir)) {
            EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
        }
    }
}

}  // namespace
}  // namespace daisy::test
