#pragma once
// Checked reading of glTF 2.0 data from a parsed tinygltf model: accessors (dense and sparse,
// bounds-checked against their buffer views and buffers) and node transforms. Internal to scene/
// (used by gltf_loader.cpp). Error messages name the accessor, buffer view, buffer or node
// ("accessors[3]: ..."); the caller prefixes the file and the place that refers to it.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/expected.h"
#include "geometry/vec3.h"
#include "scene/load_budget.h"

namespace tinygltf {
class Model;
}

namespace daisy {

// Accessor `index` as VEC3 positions widened to double, in the accessor's own units: FLOAT, or
// KHR_mesh_quantization's BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT (normalized or not).
// Refuses other types, out-of-range references, data outside its buffer view or buffer, and
// non-finite components.
Expected<std::vector<Vec3d>> readGltfPositions(const tinygltf::Model& model, int index,
                                               LoadBudget& budget);

// Accessor `index` as VEC2, VEC3 or VEC4 (`components`) of FLOAT or of integers, normalized
// ones mapped to [0, 1] or [-1, 1] (glTF 2.0 section 3.11; KHR_mesh_quantization): texture
// coordinates and vertex colours, count x components doubles. Refuses non-finite values.
Expected<std::vector<double>> readGltfAttribute(const tinygltf::Model& model, int index,
                                                int components, LoadBudget& budget);

// Accessor `index` as SCALAR UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT vertex indices.
// The values are not checked against any vertex count. Both charge what they allocate to
// `budget` before allocating it.
Expected<std::vector<uint32_t>> readGltfIndices(const tinygltf::Model& model, int index,
                                                LoadBudget& budget);

// An affine transform, column-major as glTF stores it: row r, column c is m[4 * c + r].
using GltfMatrix = std::array<double, 16>;

// Node `index`'s local transform: its `matrix`, or T * R * S from translation, rotation (unit
// quaternion x, y, z, w; normalised here) and scale. Refuses arrays of the wrong length and
// non-finite numbers. Precondition: `index` is a valid node index.
Expected<GltfMatrix> readGltfNodeTransform(const tinygltf::Model& model, int index);

// T * R * S from a translation, a quaternion (x, y, z, w; normalised here) and a scale.
// Errors ("not a unit quaternion") when the quaternion has no length.
Expected<GltfMatrix> gltfTrsMatrix(const std::array<double, 3>& translation,
                                   const std::array<double, 4>& rotation,
                                   const std::array<double, 3>& scale);

// "<what> <index> is out of range (the file has <count>)", for references between glTF arrays.
std::string gltfOutOfRange(const char* what, long long index, std::size_t count);

}  // namespace daisy
