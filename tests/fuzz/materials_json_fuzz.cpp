// libFuzzer target: any bytes as a `--materials FILE.json`, applied through loadScene to an OBJ
// scene of 64 one-triangle materials ("lamp", "wall", "m02" .. "m63", written once per process,
// the names tools/make_fuzz_corpus.py's many-member seeds use): an Error or a valid scene, never
// a crash.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_files.h"
#include "scene/load_scene.h"

namespace {

std::string writeScene() {
    std::string obj = "mtllib room.mtl\n";
    std::string mtl = "newmtl lamp\nKd 0 0 0\nKe 1 1 1\n";
    for (int k = 0; k < 64; ++k) {
        std::string name = k == 0 ? "lamp" : "wall";
        if (k >= 2) name = (k < 10 ? "m0" : "m") + std::to_string(k);
        if (k > 0) mtl += "newmtl " + name + "\nKd 0.5 0.5 0.5\n";
        const std::string x = std::to_string(k);
        obj += "v " + x + " 0 0\nv " + x + ".5 0 0\nv " + x + " 1 0\nusemtl " + name +
            "\nf -3 -2 -1\n";
    }
    daisy::fuzz::writeScratch("room.mtl", mtl);
    return daisy::fuzz::writeScratch("room.obj", obj);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string scene = writeScene();
    daisy::SceneLoadOptions options;
    options.materialsPath =
        daisy::fuzz::writeScratch("m.json", {reinterpret_cast<const char*>(data), size});
    options.maxMemoryBytes = daisy::fuzz::kFuzzMaxMemoryBytes;
    (void)daisy::loadScene(scene, options);
    return 0;
}
