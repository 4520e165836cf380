// libFuzzer target: any bytes, loaded as a .gltf, .glb or .obj scene (chosen by the first byte),
// must give a scene or an Error, never a crash, hang or sanitizer report. Build with
// -DDAISY_BUILD_FUZZERS=ON and clang; run with tools/fuzz.sh.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "geometry/patch_mesh.h"
#include "scene/load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    static const char* const kExtensions[] = {".gltf", ".glb", ".obj"};
    const char* extension = kExtensions[data[0] % 3];
    const std::string path = "/tmp/daisy_fuzz_" + std::to_string(getpid()) + std::string(extension);
    FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) return 0;
    std::fwrite(data + 1, 1, size - 1, file);
    std::fclose(file);
    daisy::SceneLoadOptions options;
    options.mtlConvention =
        data[0] & 4 ? daisy::MtlConvention::DaisyRiot : daisy::MtlConvention::Standard;
    auto scene = daisy::loadScene(path, options);
    if (scene) {
        auto patches = daisy::buildPatchMesh(scene->mesh, 0.0);
        (void)patches;
    }
    std::remove(path.c_str());
    return 0;
}
