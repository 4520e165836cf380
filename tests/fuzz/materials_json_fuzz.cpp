// libFuzzer target: any bytes as a `--materials FILE.json`, applied through loadScene to a
// two-material OBJ scene (materials "lamp" and "wall", written once per process): an Error or a
// valid scene, never a crash.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_files.h"
#include "scene/load_scene.h"

namespace {

constexpr std::string_view kObj =
    "mtllib room.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nusemtl lamp\nf 1 2 3\n"
    "usemtl wall\nf 1 4 2\n";
constexpr std::string_view kMtl = "newmtl lamp\nKd 0 0 0\nKe 1 1 1\nnewmtl wall\nKd 0.5 0.5 0.5\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string scene = [] {
        daisy::fuzz::writeScratch("room.mtl", kMtl);
        return daisy::fuzz::writeScratch("room.obj", kObj);
    }();
    daisy::SceneLoadOptions options;
    options.materialsPath =
        daisy::fuzz::writeScratch("m.json", {reinterpret_cast<const char*>(data), size});
    options.maxMemoryBytes = daisy::fuzz::kFuzzMaxMemoryBytes;
    (void)daisy::loadScene(scene, options);
    return 0;
}
