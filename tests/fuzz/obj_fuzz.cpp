// libFuzzer target: an OBJ and the MTL it names, as "<obj bytes>\n#---MTL---\n<mtl bytes>" (the
// MTL part may be absent), loaded with both MTL conventions (the first byte picks) and patched.
// The OBJ is written with "mtllib s.mtl" prepended so the MTL is always read.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_files.h"
#include "geometry/patch_mesh.h"
#include "scene/load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
    const auto [obj, mtl] = daisy::fuzz::splitAt(bytes, "\n#---MTL---\n");
    daisy::fuzz::writeScratch("s.mtl", mtl);
    const std::string path =
        daisy::fuzz::writeScratch("s.obj", "mtllib s.mtl\n" + std::string(obj));
    daisy::SceneLoadOptions options;
    options.mtlConvention =
        data[0] & 1 ? daisy::MtlConvention::DaisyRiot : daisy::MtlConvention::Standard;
    options.maxMemoryBytes = daisy::fuzz::kFuzzMaxMemoryBytes;
    auto scene = daisy::loadScene(path, options);
    if (scene) (void)daisy::buildPatchMesh(scene->mesh, 0.0, 1 << 20);
    return 0;
}
