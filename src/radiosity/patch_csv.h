#pragma once
// patches.csv (DESIGN.md section 9): a header row, then one row per patch:
// patch,triangle,area,cx,cy,cz,nx,ny,nz,material, followed by any extra column groups in the
// order given (the solver appends E_<nm> and B_<nm> per wavelength, then X,Y,Z). `patch` is
// the 0-based patch index (the row/column of F minus one in F.mtx), `triangle` the source
// triangle in scene order, `area` in scene units squared, the centroid in scene units, the unit
// face normal, and the material's name (quoted per RFC 4180 when it needs it).
#include <span>
#include <string>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"

namespace daisy {

// Extra columns: `names.size()` header cells and a row-major patches x names.size() table.
struct PatchCsvColumns {
    std::vector<std::string> names;
    std::span<const double> values;
};

// Writes through a temporary file and a rename. materialNames[m] names material index m.
// Fails (no partial file) when a column group's table has the wrong size or on I/O errors.
Expected<void> writePatchCsv(const std::string& path, const PatchMesh& mesh,
                             std::span<const std::string> materialNames,
                             std::span<const PatchCsvColumns> extra = {});

}  // namespace daisy
