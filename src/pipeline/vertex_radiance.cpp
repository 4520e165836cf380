#include "pipeline/vertex_radiance.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "core/check.h"

namespace daisy {

std::vector<float> cornerValues(const PatchMesh& mesh, std::span<const float> patchValues,
                                int channels, double creaseAngleRad,
                                std::span<const double> areaWeights) {
    DAISY_CHECK(channels > 0);
    DAISY_CHECK(areaWeights.empty() || areaWeights.size() == mesh.patchCount());
    const std::span<const double> areas = areaWeights.empty() ? mesh.areas : areaWeights;
    DAISY_CHECK(patchValues.size() == mesh.patchCount() * std::size_t(channels));
    DAISY_CHECK(mesh.vertexPatchOffsets.size() == mesh.vertexCount() + 1);
    const std::size_t stride = std::size_t(channels);
    const double cosCrease = std::cos(creaseAngleRad);
    std::vector<float> corners(mesh.patchCount() * 3 * stride);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, mesh.patchCount(), 1024),
        [&](const tbb::blocked_range<std::size_t>& range) {
            std::vector<double> sum(stride);
            for (std::size_t p = range.begin(); p != range.end(); ++p) {
                for (int c = 0; c < 3; ++c) {
                    std::fill(sum.begin(), sum.end(), 0.0);
                    double weight = 0;
                    for (const uint32_t q : mesh.patchesAtVertex(mesh.patches[p][c])) {
                        if (mesh.materials[q] != mesh.materials[p]) continue;
                        if (dot(mesh.normals[q], mesh.normals[p]) < cosCrease) continue;
                        const double area = areas[q];
                        weight += area;
                        for (std::size_t k = 0; k < stride; ++k)
                            sum[k] += area * patchValues[q * stride + k];
                    }
                    float* out = corners.data() + (p * 3 + c) * stride;
                    for (std::size_t k = 0; k < stride; ++k) {
                        // A zero-area neighbourhood keeps the patch's own value.
                        out[k] = weight > 0 ? static_cast<float>(sum[k] / weight)
                                            : patchValues[p * stride + k];
                    }
                }
            }
        });
    return corners;
}

}  // namespace daisy
