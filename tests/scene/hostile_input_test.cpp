// The library's hostile-input checks, one by one: the bounded JSON pre-pass, the GLB container,
// OBJ numbers, the load budget, the float32 range of scenes and the no-emitter warning. The
// command-line messages are covered row by row by tests/app/errors_catalogue_test.cpp.
#include <gtest/gtest.h>

#include <string>

#include "core/atomic_file.h"
#include "scene/bounded_json.h"
#include "scene/gltf_document.h"
#include "scene/load_budget.h"
#include "scene/obj_syntax.h"
#include "scene/validate_scene.h"
#include "test_util.h"

namespace daisy {
namespace {

TEST(BoundedJson, RefusesDeepNestingWithoutRecursion) {
    // 100,000 levels would overflow any recursive parser's stack; the limit is 64.
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    auto parsed = parseBoundedJson(deep);
    ASSERT_FALSE(parsed);
    EXPECT_NE(parsed.error().message.find("deeper than 64 levels"), std::string::npos);
    EXPECT_TRUE(parseBoundedJson(std::string(64, '[') + std::string(64, ']')));
}

// The depth is counted on brackets outside strings: brackets and escaped quotes inside strings
// do not count, and 64 levels around a string full of '[' still parse.
TEST(BoundedJson, CountsOnlyBracketsOutsideStrings) {
    const std::string inner = "\"" + std::string(200, '[') + "\\\"{\"";
    auto parsed = parseBoundedJson(std::string(64, '[') + inner + std::string(64, ']'));
    ASSERT_TRUE(parsed) << parsed.error().message;
    EXPECT_FALSE(parseBoundedJson(std::string(65, '[') + inner + std::string(65, ']')));
}

// An object of 40,000 object-valued members (a large --materials file) parses whole, every
// member kept.
TEST(BoundedJson, KeepsEveryMemberOfALargeObject) {
    std::string text = "{";
    for (int i = 0; i < 40000; ++i)
        text += (i ? ",\"m" : "\"m") + std::to_string(i) + "\": {\"a\": [1, 2]}";
    text += "}";
    auto parsed = parseBoundedJson(text);
    ASSERT_TRUE(parsed) << parsed.error().message;
    EXPECT_EQ(parsed->size(), 40000u);
    EXPECT_EQ((*parsed)["m39999"]["a"][1], 2);
}

TEST(BoundedJson, KeepsIntegersNullsAndEmptyMembersAsWritten) {
    // tinygltf reads 4294967296 as an int (0); nlohmann keeps the 64-bit value.
    auto parsed = parseBoundedJson(R"({"a": 4294967296, "b": null, "c": {}, "d": -4294967295})");
    ASSERT_TRUE(parsed);
    EXPECT_EQ((*parsed)["a"].get<double>(), 4294967296.0);
    EXPECT_TRUE((*parsed)["b"].is_null());
    EXPECT_TRUE((*parsed)["c"].is_object());
    EXPECT_EQ((*parsed)["d"].get<double>(), -4294967295.0);
}

// With JsonKeys::Unique a key named twice in one object is refused with the object's path; the
// same key in two different objects is fine, and the default keeps nlohmann's last-wins rule.
TEST(BoundedJson, UniqueKeysRefuseADuplicateWithItsPath) {
    const std::string nested = R"({"a": [{"b": 1}, {"c": 1, "b": 2, "b": 3}], "b": 4})";
    auto parsed = parseBoundedJson(nested, kMaxJsonDepth, JsonKeys::Unique);
    ASSERT_FALSE(parsed);
    EXPECT_EQ(parsed.error().message, "a[1]: the key \"b\" appears twice in this object");
    auto top = parseBoundedJson(R"({"x": {}, "y": 1, "x": 2})", kMaxJsonDepth, JsonKeys::Unique);
    ASSERT_FALSE(top);
    EXPECT_EQ(top.error().message, "the key \"x\" appears twice at the top level");
    auto lastWins = parseBoundedJson(nested);
    ASSERT_TRUE(lastWins);
    EXPECT_EQ((*lastWins)["a"][1]["b"], 3);
    EXPECT_TRUE(parseBoundedJson(R"({"a": {"k": 1}, "b": {"k": 2}, "c": [{"k": 1}, {"k": 2}]})",
                                 kMaxJsonDepth, JsonKeys::Unique));
}

TEST(GlbChunks, NamesTheFieldAndWhatWasExpected) {
    EXPECT_NE(splitGlb("glTF").error().message.find("fewer than the 12-byte header"),
              std::string::npos);
    std::string header = std::string("glTF") + std::string("\x02\0\0\0", 4) +
        std::string("\x14\0\0\0", 4) + std::string("\x40\0\0\0JSON", 8);
    auto split = splitGlb(header);
    ASSERT_FALSE(split);
    EXPECT_NE(split.error().message.find("GLB chunk 0 (JSON): chunkLength 64 at byte 12"),
              std::string::npos)
        << split.error().message;
}

TEST(GltfAsset, AcceptsOnlyGltf2) {
    EXPECT_TRUE(checkGltfAsset(nlohmann::json::parse(R"({"asset": {"version": "2.0"}})")));
    EXPECT_TRUE(checkGltfAsset(nlohmann::json::parse(R"({"asset": {"version": "2.1"}})")));
    EXPECT_FALSE(checkGltfAsset(nlohmann::json::parse(R"({"asset": {"version": "1.0"}})")));
    EXPECT_FALSE(checkGltfAsset(
        nlohmann::json::parse(R"({"asset": {"version": "2.0", "minVersion": "2.5"}})")));
    EXPECT_FALSE(checkGltfAsset(nlohmann::json::parse(R"({"asset": {"version": 2}})")));
}

TEST(ObjSyntax, NamesTheLineOfABadNumber) {
    auto checked = checkObjNumbers("v 0 0 0\n\nv nan 0 0\n", "a.obj");
    ASSERT_FALSE(checked);
    EXPECT_EQ(checked.error().message,
              "a.obj:3: v: 'nan' is not a finite number (expected x y z [w])");
    EXPECT_TRUE(checkObjNumbers("v 1e-3 -2 +3.5\nvt 0.5 0.5\nf 1/1 -1/1 2//3\n", "a.obj"));
    EXPECT_FALSE(checkMtlNumbers("newmtl a\nKd 0.5 hello 0.5\n", "a.mtl"));
    EXPECT_TRUE(
        checkMtlNumbers("newmtl a\nKd 0.5 0.5 0.5\nKd spectral x.rfl\nd -halo 0.5\n", "a.mtl"));
}

TEST(LoadBudget, RefusesOverTheLimitAndNeverWithoutOne) {
    LoadBudget budget(1000);
    EXPECT_TRUE(budget.charge(600, "a"));
    auto refused = budget.charge(600, "accessors[3]: count 75");
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().message.rfind("accessors[3]: count 75 needs 600 B", 0), 0u)
        << refused.error().message;
    LoadBudget unlimited;
    EXPECT_TRUE(unlimited.charge(uint64_t(1) << 62, "a"));
}

Scene square(double scale, const Vec3d& offset = {0, 0, 0}) {
    Scene scene;
    scene.path = "s.gltf";
    for (const Vec3d& p : {Vec3d{0, 0, 0}, Vec3d{1, 0, 0}, Vec3d{0, 1, 0}, Vec3d{1, 1, 0}})
        scene.mesh.positions.push_back(p * scale + offset);
    scene.mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
    scene.mesh.materials = {0, 0};
    Material lamp;
    lamp.emissiveRgb = {1, 1, 1};
    scene.materials.push_back(lamp);
    return scene;
}

// Limits from validate_scene.h (measured on the scaled Cornell box).
TEST(RayTracingRange, RefusesWhatFloat32CannotRepresent) {
    EXPECT_TRUE(checkRayTracingRange(square(1)));
    EXPECT_TRUE(checkRayTracingRange(square(1e7)));
    EXPECT_TRUE(checkRayTracingRange(square(1e-7)));
    EXPECT_FALSE(checkRayTracingRange(square(1e12)));
    EXPECT_FALSE(checkRayTracingRange(square(1e-12)));
    EXPECT_FALSE(checkRayTracingRange(square(1, {1e6, 0, 0})));  // 1 m, a million metres out
    Scene withCamera = square(1);
    withCamera.cameras.push_back(Camera{});
    withCamera.cameras[0].position = {1e18, 0, 0};
    EXPECT_FALSE(checkRayTracingRange(withCamera));
}

TEST(NoEmitterWarning, WarnsOnlyWhenNothingEmits) {
    Scene scene = square(1);
    EXPECT_EQ(noEmitterWarning(scene), "");
    scene.materials[0].emissiveRgb = {0, 0, 0};
    EXPECT_EQ(noEmitterWarning(scene).rfind("s.gltf: no surface emits light", 0), 0u);
}

TEST(AtomicOutput, ReservesThePathAndRemovesItsTemporary) {
    const auto dir = test::testTempDir();
    const std::string path = (dir / "out.txt").string();
    {
        auto reserved = AtomicOutput::open(path);
        ASSERT_TRUE(reserved);
        EXPECT_TRUE(std::filesystem::exists(temporaryPathFor(path)));
    }
    EXPECT_FALSE(std::filesystem::exists(temporaryPathFor(path)));
    EXPECT_FALSE(AtomicOutput::open((dir / "missing" / "x").string()));
    EXPECT_FALSE(AtomicOutput::open(dir.string()));
    // Reserved, then written: the temporary becomes the file.
    auto reserved = AtomicOutput::open(path);
    ASSERT_TRUE(reserved);
    ASSERT_TRUE(writeFileAtomically(path, [](std::FILE* f) {
        std::fputs("x", f);
        return std::string();
    }));
    EXPECT_TRUE(std::filesystem::exists(path));
    EXPECT_FALSE(std::filesystem::exists(temporaryPathFor(path)));
}

// A writer killed outright leaves "<path>.tmp-<pid>"; the next write of the same path removes it
// when that process is gone, and leaves a live writer's temporary and other files' alone.
TEST(AtomicOutput, RemovesTheTemporariesOfKilledWriters) {
    const auto dir = test::testTempDir();
    const std::string path = (dir / "out.png").string();
    const std::string dead = "out.png.tmp-" + std::to_string(test::deadPid());
    const std::string live = "out.png.tmp-" + std::to_string(getppid());
    const std::string other = "other.png.tmp-" + std::to_string(test::deadPid());
    for (const std::string& name : {dead, live, other})
        test::writeFile(dir, name, "partial");
    auto reserved = AtomicOutput::open(path);
    ASSERT_TRUE(reserved);
    EXPECT_FALSE(std::filesystem::exists(dir / dead));
    EXPECT_TRUE(std::filesystem::exists(dir / live));
    EXPECT_TRUE(std::filesystem::exists(dir / other));
}

}  // namespace
}  // namespace daisy
