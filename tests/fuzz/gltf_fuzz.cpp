// libFuzzer target: any bytes as a .gltf or .glb scene (the first byte's low bit picks), loaded
// with loadScene under a 256 MiB load budget and patched, must give a scene or an Error: never a
// crash, hang or sanitizer report. Seeds: tests/fuzz/corpus/gltf (tools/make_fuzz_corpus.py).
#include <cstddef>
#include <cstdint>

#include "fuzz_files.h"
#include "geometry/patch_mesh.h"
#include "scene/load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
    const std::string path = daisy::fuzz::writeScratch(data[0] & 1 ? "s.glb" : "s.gltf", bytes);
    daisy::SceneLoadOptions options;
    options.maxMemoryBytes = daisy::fuzz::kFuzzMaxMemoryBytes;
    auto scene = daisy::loadScene(path, options);
    if (scene) (void)daisy::buildPatchMesh(scene->mesh, 0.0, 1 << 20);
    return 0;
}
