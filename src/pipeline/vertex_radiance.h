#pragma once
// Smooth shading values per patch corner (DESIGN.md section 7): the value at a corner is the
// area-weighted mean of the patch values of the patches sharing that vertex position, taken only
// over those with the same material whose normal is within the crease angle of this patch's
// normal, so light does not bleed across creases or material boundaries.
#include <span>
#include <vector>

#include "geometry/patch_mesh.h"

namespace daisy {

// Dihedral angle above which two patches sharing a vertex are shaded apart (radians; 30 deg).
inline constexpr double kCreaseAngleRad = 0.5235987755982988;

// patchValues: patchCount x channels (row-major). Returns patchCount x 3 x channels: corner c of
// patch p at [(p * 3 + c) * channels]. areaWeights (one per patch, empty = mesh.areas) replaces
// the patch areas in the means (the gather's exposed areas, radiosity/patch_exposure.h).
std::vector<float> cornerValues(const PatchMesh& mesh, std::span<const float> patchValues,
                                int channels, double creaseAngleRad = kCreaseAngleRad,
                                std::span<const double> areaWeights = {});

}  // namespace daisy
