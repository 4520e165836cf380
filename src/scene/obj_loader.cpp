#include "scene/obj_loader.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "core/strings.h"
#include "scene/load_budget.h"
#include "scene/obj_syntax.h"

// How MTL values become materials (DESIGN.md section 10):
// - Standard: Kd -> baseColor (each component in [0, 1]), Ke -> emissiveRgb (each >= 0); Ks and
//   every other MTL statement are ignored.
// - DaisyRiot (the original program's convention), in addition:
//   * Ks not all zero -> spectral.fluorescence = FluorescentColor{Ks} (each component in [0, 1]):
//     the colour the surface fluoresces with under UV;
//   * Kd all zero and Ke not all zero -> a UV lamp: spectral.emission = blacklight preset with
//     scale = max(Ke), and emissiveRgb cleared so the RGB emission does not count twice.
// Faces without a material (no usemtl, or a name the MTL files lack) share one "default"
// material of 0.8 grey, appended after the MTL materials when any face needs it.

namespace daisy {
namespace {

constexpr double kDefaultGrey = 0.8;
constexpr double kNoUpperLimit = std::numeric_limits<double>::infinity();

using Rgb = std::array<double, 3>;

Rgb toRgb(const tinyobj::real_t (&values)[3]) {
    return {double(values[0]), double(values[1]), double(values[2])};
}

bool isZero(const Rgb& rgb) {
    return rgb[0] == 0 && rgb[1] == 0 && rgb[2] == 0;
}

// "0.1 0.9 0.2", as an MTL file writes it (6 significant digits, where concat gives 17).
std::string formatRgb(const Rgb& rgb) {
    std::ostringstream out;
    out << rgb[0] << ' ' << rgb[1] << ' ' << rgb[2];
    return out.str();
}

// tinyobjloader's multi-line messages as single lines, without blanks or stray punctuation.
std::vector<std::string> splitMessage(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) {
            line.pop_back();
        }
        if (std::any_of(line.begin(), line.end(),
                        [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; })) {
            lines.push_back(line);
        }
    }
    return lines;
}

// The 1-based line of the file that holds the (0-based) vertex'th "v" statement, or 0.
std::size_t vertexLine(const std::string& path, std::size_t vertex) {
    std::ifstream in(path, std::ios::binary);
    std::string line;
    std::size_t lineNumber = 0, seen = 0;
    while (std::getline(in, line)) {
        ++lineNumber;
        const std::size_t start = line.find_first_not_of(" \t");
        if (start == std::string::npos || line.size() < start + 2 || line[start] != 'v') continue;
        if (line[start + 1] != ' ' && line[start + 1] != '\t') continue;
        if (seen++ == vertex) return lineNumber;
    }
    return 0;
}

// Checks `rgb` (statement `key` of `material`) is finite and within [0, maxValue].
Expected<void> checkRgb(const Rgb& rgb, const Material& material, const char* key,
                        double maxValue) {
    for (double component : rgb) {
        if (!std::isfinite(component) || component < 0 || component > maxValue) {
            const std::string range =
                std::isinf(maxValue) ? "must be finite and >= 0" : "must each be in [0, 1]";
            return Error{
                concat(material.origin, ": ", key, " ", formatRgb(rgb), ": components ", range)};
        }
    }
    return {};
}

Expected<Material> convertMaterial(const tinyobj::material_t& source, const std::string& path,
                                   MtlConvention convention) {
    Material material;
    material.name = source.name;
    material.origin = concat(path, ": material '", source.name, "'");
    const Rgb kd = toRgb(source.diffuse);
    const Rgb ke = toRgb(source.emission);
    const Rgb ks = toRgb(source.specular);
    if (auto checked = checkRgb(kd, material, "Kd", 1.0); !checked) return checked.error();
    if (auto checked = checkRgb(ke, material, "Ke", kNoUpperLimit); !checked)
        return checked.error();
    material.baseColor = kd;
    material.emissiveRgb = ke;
    if (convention == MtlConvention::DaisyRiot) {
        if (!isZero(ks)) {
            if (auto checked = checkRgb(ks, material, "Ks", 1.0); !checked) {
                return checked.error();
            }
            material.spectral.fluorescence = FluorescentColor{ks};
        }
        if (isZero(kd) && !isZero(ke)) {
            const double peak = std::max({ke[0], ke[1], ke[2]});
            material.spectral.emission = SpectrumSpec{PresetSpectrum{"blacklight"}, peak};
            material.emissiveRgb = {0, 0, 0};
        }
    }
    return material;
}

// Reads `path` whole, charged to `budget`; "" with ok = false when it cannot be read.
Expected<std::string> readText(const std::string& path, LoadBudget& budget) {
    std::error_code ec;
    const uint64_t bytes = std::filesystem::file_size(path, ec);
    if (ec) return Error{path + ": cannot read: " + ec.message()};
    // tinyobjloader holds the text and its arrays: charge about four times the file.
    if (auto charged = budget.charge(bytes * 4, concat(path, " (", bytes, " bytes)")); !charged) {
        return charged.error();
    }
    std::ifstream in(path, std::ios::binary);
    std::string text(bytes, '\0');
    in.read(text.data(), static_cast<std::streamsize>(bytes));
    if (!in && bytes > 0) return Error{path + ": cannot read"};
    return text;
}

// Checks the numbers of the OBJ and of every MTL file it names that exists (obj_syntax.h).
Expected<void> checkObjAndMtlNumbers(const std::string& path, LoadBudget& budget) {
    auto text = readText(path, budget);
    if (!text) return text.error();
    if (auto ok = checkObjNumbers(*text, path); !ok) return ok;
    const std::filesystem::path folder = std::filesystem::path(path).parent_path();
    for (const std::string& name : objMaterialLibraries(*text)) {
        const std::string mtl = (folder / name).string();
        std::error_code ec;
        if (!std::filesystem::is_regular_file(mtl, ec)) continue;  // tinyobjloader warns
        auto mtlText = readText(mtl, budget);
        if (!mtlText) return mtlText.error();
        if (auto ok = checkMtlNumbers(*mtlText, mtl); !ok) return ok;
    }
    return {};
}

}  // namespace

Expected<Scene> loadObj(const std::string& path, MtlConvention convention,
                        uint64_t maxMemoryBytes) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        return Error{
            path + (std::filesystem::exists(path, ec) ? ": not a regular file" : ": no such file")};
    }
    LoadBudget budget(maxMemoryBytes);
    if (auto ok = checkObjAndMtlNumbers(path, budget); !ok) return ok.error();
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    const std::string folder = std::filesystem::path(path).parent_path().string();
    config.mtl_search_path = folder.empty() ? "." : folder;

    tinyobj::ObjReader reader;
    const bool parsed = reader.ParseFromFile(path, config);
    Scene scene;
    scene.path = path;
    for (const std::string& line : splitMessage(reader.Warning())) {
        scene.warnings.push_back(path + ": " + line);
    }
    if (!parsed) {
        std::string message;
        for (const std::string& line : splitMessage(reader.Error())) {
            message += (message.empty() ? "" : "; ") + line;
        }
        return Error{path + ": " + (message.empty() ? "cannot be parsed as OBJ" : message)};
    }
    for (const std::string& line : splitMessage(reader.Error())) {
        scene.warnings.push_back(path + ": " + line);  // reported, but the reader carried on
    }

    const std::vector<tinyobj::real_t>& coordinates = reader.GetAttrib().vertices;
    const std::size_t vertexCount = coordinates.size() / 3;
    if (vertexCount > std::numeric_limits<uint32_t>::max()) {
        return Error{concat(path, ": ", vertexCount, " vertices; at most 2^32 - 1 are supported")};
    }
    scene.mesh.positions.reserve(vertexCount);
    for (std::size_t v = 0; v < vertexCount; ++v) {
        const Vec3d position{double(coordinates[3 * v]), double(coordinates[3 * v + 1]),
                             double(coordinates[3 * v + 2])};
        if (!isFinite(position)) {
            const std::size_t line = vertexLine(path, v);
            return Error{concat(path, ": vertex ", v + 1,
                                line > 0 ? concat(" (line ", line, ")") : "",
                                " has a non-finite coordinate ", position)};
        }
        scene.mesh.positions.push_back(position);
    }

    for (const tinyobj::material_t& source : reader.GetMaterials()) {
        auto material = convertMaterial(source, path, convention);
        if (!material) return material.error();
        scene.materials.push_back(std::move(*material));
    }
    const std::size_t mtlMaterialCount = scene.materials.size();
    std::size_t defaultMaterial = std::numeric_limits<std::size_t>::max();

    // Vertex indices and face numbers in messages are 1-based, as in the file.
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        const tinyobj::mesh_t& mesh = shape.mesh;
        const std::string shapeName = shape.name.empty() ? "(unnamed)" : "'" + shape.name + "'";
        std::size_t first = 0;
        for (std::size_t face = 0; face < mesh.num_face_vertices.size(); ++face) {
            const std::size_t cornerCount = mesh.num_face_vertices[face];
            if (first + cornerCount > mesh.indices.size()) {
                return Error{concat(path, ": shape ", shapeName, " face ", face + 1,
                                    ": its vertex list is truncated")};
            }
            std::vector<uint32_t> corners;
            for (std::size_t k = 0; k < cornerCount; ++k) {
                const int index = mesh.indices[first + k].vertex_index;
                if (index < 0 || std::size_t(index) >= vertexCount) {
                    // A negative result comes from a relative index reaching before vertex 1.
                    const std::string what = index < 0
                        ? std::string("a relative vertex index reaches before vertex 1")
                        : concat("vertex index ", index + 1, " is out of range");
                    return Error{concat(path, ": shape ", shapeName, " face ", face + 1, ": ", what,
                                        " (", vertexCount, " vertices)")};
                }
                corners.push_back(uint32_t(index));
            }
            first += cornerCount;

            const int id = face < mesh.material_ids.size() ? mesh.material_ids[face] : -1;
            std::size_t material = std::size_t(id);
            if (id < 0 || material >= mtlMaterialCount) {
                if (defaultMaterial == std::numeric_limits<std::size_t>::max()) {
                    defaultMaterial = scene.materials.size();
                    Material grey;
                    grey.name = "default";
                    grey.origin = path + ": faces without a material";
                    grey.baseColor = {kDefaultGrey, kDefaultGrey, kDefaultGrey};
                    scene.materials.push_back(grey);
                }
                material = defaultMaterial;
            }
            // The reader triangulates, so cornerCount is 3; a fan covers anything it leaves.
            for (std::size_t k = 1; k + 1 < cornerCount; ++k) {
                scene.mesh.triangles.push_back({corners[0], corners[k], corners[k + 1]});
                scene.mesh.materials.push_back(uint32_t(material));
            }
        }
    }
    return scene;
}

}  // namespace daisy
