#include "radiosity/patch_csv.h"

#include <charconv>

#include "core/atomic_file.h"
#include "core/strings.h"

namespace daisy {
namespace {

// RFC 4180: quote a field containing a comma, quote or line break; double inner quotes.
std::string csvField(const std::string& text) {
    if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
    std::string out = "\"";
    for (char c : text) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

// Shortest text that reads back as the same double; -0 is written as 0.
void appendNumber(std::string& line, double value) {
    char buffer[32];
    line.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, value + 0.0).ptr);
}

}  // namespace

Expected<void> writePatchCsv(const std::string& path, const PatchMesh& mesh,
                             std::span<const std::string> materialNames,
                             std::span<const PatchCsvColumns> extra) {
    const std::size_t n = mesh.patchCount();
    for (const PatchCsvColumns& group : extra) {
        if (group.values.size() != n * group.names.size()) {
            return Error{concat(
                path, ": column group '", group.names.empty() ? std::string() : group.names.front(),
                "...' has ", group.values.size(), " values, expected ", n * group.names.size())};
        }
    }
    return writeFileAtomically(path, [&](std::FILE* file) -> std::string {
        std::string line = "patch,triangle,area,cx,cy,cz,nx,ny,nz,material";
        for (const PatchCsvColumns& group : extra) {
            for (const std::string& name : group.names) {
                line += ',';
                line += csvField(name);
            }
        }
        line += '\n';
        std::fputs(line.c_str(), file);
        for (std::size_t p = 0; p < n; ++p) {
            line.clear();
            line += std::to_string(p);
            line += ',';
            line += std::to_string(mesh.sourceTriangle[p]);
            for (double value :
                 {mesh.areas[p], mesh.centroids[p].x, mesh.centroids[p].y, mesh.centroids[p].z,
                  mesh.normals[p].x, mesh.normals[p].y, mesh.normals[p].z}) {
                line += ',';
                appendNumber(line, value);
            }
            const uint32_t material = mesh.materials[p];
            line += ',';
            line += material < materialNames.size() ? csvField(materialNames[material])
                                                    : std::to_string(material);
            for (const PatchCsvColumns& group : extra) {
                const std::size_t width = group.names.size();
                for (std::size_t k = 0; k < width; ++k) {
                    line += ',';
                    appendNumber(line, group.values[p * width + k]);
                }
            }
            line += '\n';
            if (std::fwrite(line.data(), 1, line.size(), file) != line.size()) {
                return "write failed";
            }
        }
        return "";
    });
}

}  // namespace daisy
