// Fuzzer builds only: compiles the implementations of the system (Debian) tinygltf and
// tinyobjloader headers into each fuzzer, so the sanitizers and libFuzzer's coverage see inside
// them (the shared libraries daisy_core links are not instrumented). The executable's
// definitions take precedence over the libraries' at link time. Nothing is vendored: these are
// the packaged headers, with the same configuration daisy_core uses (tinyobjloader in double).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>

#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
