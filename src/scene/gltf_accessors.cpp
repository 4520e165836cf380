#include "scene/gltf_accessors.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <tuple>

#include "core/strings.h"

namespace daisy {
namespace {

static_assert(std::endian::native == std::endian::little, "glTF buffers are little-endian");

// Element counts are capped so that every vertex stays addressable by a uint32_t index.
constexpr std::size_t kMaxElementCount = std::numeric_limits<uint32_t>::max();

const char* typeName(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return "SCALAR";
        case TINYGLTF_TYPE_VEC2:
            return "VEC2";
        case TINYGLTF_TYPE_VEC3:
            return "VEC3";
        case TINYGLTF_TYPE_VEC4:
            return "VEC4";
        case TINYGLTF_TYPE_MAT2:
            return "MAT2";
        case TINYGLTF_TYPE_MAT3:
            return "MAT3";
        case TINYGLTF_TYPE_MAT4:
            return "MAT4";
        default:
            return "unknown type";
    }
}

const char* componentTypeName(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return "BYTE";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return "UNSIGNED_BYTE";
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return "SHORT";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return "UNSIGNED_SHORT";
        case TINYGLTF_COMPONENT_TYPE_INT:
            return "INT";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            return "UNSIGNED_INT";
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return "FLOAT";
        default:
            return "unknown component type";
    }
}

bool isUnsignedIndexType(int componentType) {
    return componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
        componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
        componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

// How one element is stored: `components` values of `componentType`, `componentSize` bytes each.
struct Layout {
    int componentType = 0;
    std::size_t components = 0;
    std::size_t componentSize = 0;
};

Layout layoutOf(int type, int componentType) {
    return {componentType, static_cast<std::size_t>(tinygltf::GetNumComponentsInType(type)),
            static_cast<std::size_t>(tinygltf::GetComponentSizeInBytes(componentType))};
}

// Whether `count` elements of `elementSize` bytes, `stride` bytes apart and starting at `offset`,
// lie inside `size` bytes, without overflowing. Precondition: stride > 0.
bool fits(std::size_t offset, std::size_t stride, std::size_t count, std::size_t elementSize,
          std::size_t size) {
    if (count == 0) return offset <= size;
    if (offset > size || elementSize > size - offset) return false;
    return count - 1 <= (size - offset - elementSize) / stride;
}

double readComponent(const unsigned char* bytes, int componentType) {
    auto load = [bytes]<typename T>(T value) {
        std::memcpy(&value, bytes, sizeof(T));
        return static_cast<double>(value);
    };
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return load(int8_t{});
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return load(uint8_t{});
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return load(int16_t{});
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return load(uint16_t{});
        case TINYGLTF_COMPONENT_TYPE_INT:
            return load(int32_t{});
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            return load(uint32_t{});
        default:
            return load(float{});
    }
}

// `count` elements laid out as `layout`, starting `byteOffset` bytes into buffer view `viewIndex`,
// as count x components doubles. `where` names the reader for messages ("accessors[3]").
Expected<std::vector<double>> readView(const tinygltf::Model& model, int viewIndex,
                                       std::size_t byteOffset, std::size_t count,
                                       const Layout& layout, const std::string& where) {
    if (viewIndex < 0 || static_cast<std::size_t>(viewIndex) >= model.bufferViews.size()) {
        return Error{where + ": " +
                     gltfOutOfRange("bufferView", viewIndex, model.bufferViews.size())};
    }
    const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(viewIndex)];
    const std::string viewWhere = concat("bufferViews[", viewIndex, "]");
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
        return Error{viewWhere + ": " +
                     gltfOutOfRange("buffer", view.buffer, model.buffers.size())};
    }
    const std::vector<unsigned char>& data =
        model.buffers[static_cast<std::size_t>(view.buffer)].data;
    if (!fits(view.byteOffset, 1, 1, view.byteLength, data.size())) {
        return Error{concat(viewWhere, ": bytes [", view.byteOffset, ", ",
                            view.byteOffset + view.byteLength, ") exceed buffers[", view.buffer,
                            "] (", data.size(), " bytes)")};
    }
    const std::size_t elementSize = layout.components * layout.componentSize;
    const std::size_t stride = view.byteStride != 0 ? view.byteStride : elementSize;
    if (stride < elementSize) {
        return Error{concat(viewWhere, ": byteStride ", stride, " is smaller than the ",
                            elementSize, "-byte elements of ", where)};
    }
    if (!fits(byteOffset, stride, count, elementSize, view.byteLength)) {
        return Error{concat(where, ": ", count, " elements of ", elementSize, " bytes, ", stride,
                            " apart from byte ", byteOffset, ", exceed ", viewWhere, " (",
                            view.byteLength, " bytes)")};
    }
    std::vector<double> values(count * layout.components);
    const unsigned char* first = data.data() + view.byteOffset + byteOffset;
    for (std::size_t i = 0; i < count; ++i) {
        for (std::size_t c = 0; c < layout.components; ++c) {
            values[i * layout.components + c] =
                readComponent(first + i * stride + c * layout.componentSize, layout.componentType);
        }
    }
    return values;
}

// Overwrites the elements a sparse accessor substitutes (glTF 2.0 section 3.6.2.3).
Expected<void> applySparse(const tinygltf::Model& model, const tinygltf::Accessor& accessor,
                           const Layout& layout, const std::string& where,
                           std::vector<double>& values) {
    const auto& sparse = accessor.sparse;
    const std::string sparseWhere = where + ".sparse";
    if (sparse.count < 0 || static_cast<std::size_t>(sparse.count) > accessor.count) {
        return Error{
            concat(sparseWhere, ".count: ", sparse.count, " is outside [0, ", accessor.count, "]")};
    }
    if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0) {
        return Error{sparseWhere + ": negative byteOffset"};
    }
    if (!isUnsignedIndexType(sparse.indices.componentType)) {
        return Error{concat(sparseWhere, ".indices.componentType: ",
                            componentTypeName(sparse.indices.componentType),
                            " is not UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT")};
    }
    const auto count = static_cast<std::size_t>(sparse.count);
    auto targets = readView(model, sparse.indices.bufferView,
                            static_cast<std::size_t>(sparse.indices.byteOffset), count,
                            layoutOf(TINYGLTF_TYPE_SCALAR, sparse.indices.componentType),
                            sparseWhere + ".indices");
    if (!targets) return targets.error();
    auto substitutes = readView(model, sparse.values.bufferView,
                                static_cast<std::size_t>(sparse.values.byteOffset), count, layout,
                                sparseWhere + ".values");
    if (!substitutes) return substitutes.error();
    for (std::size_t k = 0; k < count; ++k) {
        const auto target = static_cast<std::size_t>((*targets)[k]);
        if (target >= accessor.count) {
            return Error{concat(sparseWhere, ".indices[", k, "]: element ", target,
                                " is out of range (the accessor has ", accessor.count, ")")};
        }
        std::copy_n(substitutes->begin() + static_cast<std::ptrdiff_t>(k * layout.components),
                    layout.components,
                    values.begin() + static_cast<std::ptrdiff_t>(target * layout.components));
    }
    return {};
}

// Accessor `index` as count x components doubles, after checking that its type is `type` and its
// component type one of `componentTypes` (described to the user as `required`).
Expected<std::vector<double>> readAccessor(const tinygltf::Model& model, int index, int type,
                                           std::initializer_list<int> componentTypes,
                                           const char* required, LoadBudget& budget) {
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
        return Error{gltfOutOfRange("accessor", index, model.accessors.size())};
    }
    const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(index)];
    const std::string where = concat("accessors[", index, "]");
    if (accessor.type != type ||
        std::find(componentTypes.begin(), componentTypes.end(), accessor.componentType) ==
            componentTypes.end()) {
        return Error{concat(where, ": ", typeName(accessor.type), " ",
                            componentTypeName(accessor.componentType), " where ", required,
                            " is required")};
    }
    if (accessor.count > kMaxElementCount) {
        return Error{concat(where, ": count ", accessor.count, " exceeds ", kMaxElementCount)};
    }
    const Layout layout = layoutOf(type, accessor.componentType);
    // The values as doubles plus the caller's typed copy: about twice this.
    const uint64_t bytes = uint64_t(accessor.count) * layout.components * sizeof(double) * 2;
    if (auto charged = budget.charge(
            bytes, concat(where, ": count ", accessor.count, " (", typeName(type), ")"));
        !charged) {
        return charged.error();
    }
    std::vector<double> values;
    if (accessor.bufferView != -1) {
        auto dense = readView(model, accessor.bufferView, accessor.byteOffset, accessor.count,
                              layout, where);
        if (!dense) return dense.error();
        values = std::move(*dense);
    } else {
        values.assign(accessor.count * layout.components, 0.0);  // glTF: no bufferView = zeros
    }
    if (accessor.sparse.isSparse) {
        auto applied = applySparse(model, accessor, layout, where, values);
        if (!applied) return applied.error();
    }
    return values;
}

// Checks an optional fixed-length number array of a node (empty = absent).
Expected<void> checkNumbers(const std::vector<double>& values, std::size_t size,
                            const std::string& where) {
    if (!values.empty() && values.size() != size) {
        return Error{concat(where, ": has ", values.size(), " numbers, expected ", size)};
    }
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (!std::isfinite(values[i])) {
            return Error{concat(where, "[", i, "]: ", values[i], " is not finite")};
        }
    }
    return {};
}

}  // namespace

Expected<GltfMatrix> readGltfNodeTransform(const tinygltf::Model& model, int index) {
    const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(index)];
    const std::string where = concat("nodes[", index, "]");
    for (const auto& [values, name, size] :
         {std::tuple{&node.matrix, "matrix", 16}, std::tuple{&node.translation, "translation", 3},
          std::tuple{&node.rotation, "rotation", 4}, std::tuple{&node.scale, "scale", 3}}) {
        auto checked = checkNumbers(*values, static_cast<std::size_t>(size), where + "." + name);
        if (!checked) return checked.error();
    }
    GltfMatrix m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    if (!node.matrix.empty()) {
        std::copy(node.matrix.begin(), node.matrix.end(), m.begin());
        return m;
    }
    std::array<double, 3> t{0, 0, 0}, scale{1, 1, 1};
    std::array<double, 4> q{0, 0, 0, 1};
    if (!node.translation.empty()) std::copy_n(node.translation.begin(), 3, t.begin());
    if (!node.rotation.empty()) std::copy(node.rotation.begin(), node.rotation.end(), q.begin());
    if (!node.scale.empty()) std::copy_n(node.scale.begin(), 3, scale.begin());
    auto trs = gltfTrsMatrix(t, q, scale);
    if (!trs) return Error{where + ".rotation: " + trs.error().message};
    return trs;
}

Expected<GltfMatrix> gltfTrsMatrix(const std::array<double, 3>& translation,
                                   const std::array<double, 4>& q,
                                   const std::array<double, 3>& scale) {
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(norm > 0) || !std::isfinite(norm)) return Error{"not a unit quaternion"};
    const double x = q[0] / norm, y = q[1] / norm, z = q[2] / norm, w = q[3] / norm;
    const double rotation[3][3] = {
        {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
        {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
        {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    GltfMatrix m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    for (int c = 0; c < 3; ++c) {
        for (int r = 0; r < 3; ++r)
            m[4 * c + r] = rotation[r][c] * scale[static_cast<std::size_t>(c)];
        m[12 + c] = translation[static_cast<std::size_t>(c)];
    }
    return m;
}

std::string gltfOutOfRange(const char* what, long long index, std::size_t count) {
    return concat(what, " ", index, " is out of range (the file has ", count, ")");
}

namespace {

// glTF 2.0 section 3.11 (normalized integers): the float a stored component stands for.
void normalize(const tinygltf::Model& model, int index, std::vector<double>& values) {
    const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(index)];
    if (!accessor.normalized) return;
    double scale = 1;
    bool isSigned = false;
    switch (accessor.componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            scale = 127, isSigned = true;
            break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            scale = 255;
            break;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            scale = 32767, isSigned = true;
            break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            scale = 65535;
            break;
        default:
            return;
    }
    for (double& value : values)
        value = isSigned ? std::max(value / scale, -1.0) : value / scale;
}

constexpr std::initializer_list<int> kQuantizedTypes = {
    TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE,
    TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT,
    TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};

}  // namespace

Expected<std::vector<double>> readGltfAttribute(const tinygltf::Model& model, int index,
                                                int components, LoadBudget& budget) {
    const int type = components == 2 ? TINYGLTF_TYPE_VEC2
        : components == 3            ? TINYGLTF_TYPE_VEC3
                                     : TINYGLTF_TYPE_VEC4;
    const char* required = components == 2 ? "VEC2 FLOAT or (normalized) integers"
        : components == 3                  ? "VEC3 FLOAT or (normalized) integers"
                                           : "VEC4 FLOAT or (normalized) integers";
    auto values = readAccessor(model, index, type, kQuantizedTypes, required, budget);
    if (!values) return values.error();
    normalize(model, index, *values);
    for (std::size_t i = 0; i < values->size(); ++i) {
        if (!std::isfinite((*values)[i])) {
            return Error{concat("accessors[", index, "]: element ", i / std::size_t(components),
                                " is not finite")};
        }
    }
    return values;
}

Expected<std::vector<Vec3d>> readGltfPositions(const tinygltf::Model& model, int index,
                                               LoadBudget& budget) {
    // KHR_mesh_quantization allows (normalized) byte and short positions; the node transform
    // scales them back.
    auto values = readAccessor(model, index, TINYGLTF_TYPE_VEC3, kQuantizedTypes,
                               "VEC3 FLOAT (or KHR_mesh_quantization's BYTE or SHORT)", budget);
    if (!values) return values.error();
    normalize(model, index, *values);
    std::vector<Vec3d> positions(values->size() / 3);
    for (std::size_t i = 0; i < positions.size(); ++i) {
        positions[i] = {(*values)[3 * i], (*values)[3 * i + 1], (*values)[3 * i + 2]};
        if (!isFinite(positions[i])) {
            return Error{
                concat("accessors[", index, "]: element ", i, " is not finite ", positions[i])};
        }
    }
    return positions;
}

Expected<std::vector<uint32_t>> readGltfIndices(const tinygltf::Model& model, int index,
                                                LoadBudget& budget) {
    auto values =
        readAccessor(model, index, TINYGLTF_TYPE_SCALAR,
                     {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                     "SCALAR UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT", budget);
    if (!values) return values.error();
    std::vector<uint32_t> indices(values->size());
    std::transform(values->begin(), values->end(), indices.begin(),
                   [](double value) { return static_cast<uint32_t>(value); });
    return indices;
}

}  // namespace daisy
