#pragma once
// Near-field indirect gather at render time (docs/rendering.md). The smooth
// image holds each patch's area mean of the light it gathers, interpolated over vertices, which
// averages away the peak of the interreflected light in a concave corner: at a point x a
// fraction of a patch from a crease, the neighbour across the crease fills up to half of x's
// hemisphere, where the patch mean sees much less of it.
//
// Split of the indirect gather G_i - D_i = sum_j F_ij (B_j - E_j) (final_gather.h) into a near
// part, over the patches j whose centroids lie within the radius R of the receiver, and a far
// part. At a point x on patch i the near part uses the exact point-to-triangle factor (Lambert's
// contour formula, shared/formfactor.h), window-weighted by distance:
//     Near(x) = sum_{j near i} w(|x - c_j|) v_ij F(x -> j) (B_j - E_j),
//     Omega(x) = sum_{j near i} w(|x - c_j|) v_ij F(x -> j)   (the share of x's hemisphere),
// w = 1 up to 3R / 4, a smoothstep to 0 at R; v_ij the pair's visibility, F_ij over the mean of
// the unoccluded F(x -> j), set to 1 within 5% of 1 (the rule's own error, not occlusion). Both
// are evaluated at the 15 nodes of a 4 x 4 lattice on each patch (pulled 1e-3 towards the
// centroid, so a node on a crease sees the neighbour's limit) and interpolated linearly per
// sample: the image is exact at the nodes and has no per-sample cost beyond the interpolation.
// A patch whose lattice cannot follow one of its neighbours (a small neighbour standing on it,
// whose light falls on a strip narrower than the nodes' spacing) is evaluated exactly at each
// sample instead, over all its neighbours (near_field.cpp: kLatticeTolerance).
// The far part fills the rest of the hemisphere, 1 - Omega(x), with the patch's mean far
// radiosity: with N_i and Omega_i the means of the interpolants over i,
//     Far(x) = (1 - Omega(x)) (G_i - D_i - N_i) / (1 - Omega_i),
// so a point in a crease, where the neighbour covers half the hemisphere, trades far light for
// near light instead of adding it. The image is, per sample (S the smooth image of
// S_i = E_i + M_i (G_i - D_i - N_i) / (1 - Omega_i), E_i what the patch emits itself and
// P the punctual lights' direct light, final_gather.h):
//     S(x) + [M_i H(x) + M_i P(x) + M_i Near(x)] / pi - Omega(x) (S(x) - E_i / pi),
// whose patch mean is B_i / pi (light moved within patches, none added). In a closed room of
// uniform E and rho it is B = E / (1 - rho) at every point; where no near patch is in view it
// is the direct gather's image. Patches partly buried under an object (patch_exposure.h) take
// their exposed part's values: (B_j - E_j) / phi_j as a neighbour, means over the exposed
// children of the lattice, and the smooth value over phi_i; phi is floored at 1/4 for these
// divisions (the solve already gave the exposed parts all the light they gather:
// pipeline/session.h). Deterministic: no random numbers. The emitters' own E is never gathered
// (the direct gather's), and B_j - E_j carries what reached j directly.
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/patch_mesh.h"
#include "radiosity/patch_exposure.h"
#include "radiosity/radiosity_system.h"
#include "radiosity/transport.h"
#include "raycast/ray.h"
#include "shared/gpu_types.h"

namespace daisy {

struct NearFieldSettings {
    // R in patch sizes (the median longest patch edge); 0 = no near field, only the buried
    // parts (patch_exposure.h).
    double radius = 2;
    // Most neighbours a receiving patch keeps (the nearest by centroid distance), so a scene of
    // a few large triangles does not gather every patch at every lattice node.
    int maxNeighbours = 256;
};

class NearField {
public:
    // Per receiving patch: Near and Omega at its 15 lattice nodes (or the list of neighbours
    // it gathers exactly per sample) over the patches j with F_ij > 0 (the transport's row i) that
    // can lie within R of it, their means N_i and Omega_i over its exposed children. `radiosity`:
    // the solved B (n x m, the system's layout). `receivers`: per patch, whether to build its
    // part (empty: every patch); the others gather nothing near, as a patch without near
    // neighbours. Parallel over patches (the caller's TBB arena); deterministic.
    static NearField build(const PatchMesh& patches, const RadiositySystem& system,
                           const Transport& transport, std::span<const double> radiosity,
                           const PatchExposure& exposure, const NearFieldSettings& settings,
                           std::span<const uint8_t> receivers = {});

    // From the direct gather's smooth part b = B - M D - M P (n x m), in place: S_i above (b_i
    // for patches without near neighbours), E_i what the patch emits itself (the system's
    // emission without its punctualEmission).
    void toFarRadiosity(const RadiositySystem& system, std::span<double> b) const;

    // Keeps the smooth image's corner values (vertex_radiance.h's layout) and each patch's
    // emission E_i / pi in the same `channels` (final_gather.h's radiosityChannels), which
    // removeCovered reads.
    void setSmoothImage(std::vector<float> corners, std::vector<float> emission, int channels);

    // Adds Near(x) (m values, W m^-2 nm^-1 of irradiance) at the point of patch `patch` with
    // the hit's barycentrics (u weights corner 1, v corner 2), and returns Omega(x). Thread-safe.
    double addIrradiance(uint32_t patch, float u, float v, std::span<double> irradiance) const;

    // values[c] -= omega (S(hit) - E_i / pi)[c] for the first values.size() channels (no
    // coverage). Precondition: setSmoothImage was called.
    void removeCovered(const SurfaceHit& hit, double omega, std::span<double> values) const;

    bool empty() const { return nodes_.empty() && exact_.empty(); }
    std::size_t pairCount() const { return pairCount_; }
    // The neighbour pairs of the patches gathered exactly at every sample (of pairCount()).
    std::size_t exactPairCount() const { return exact_.size(); }
    double radius() const { return radius_; }

private:
    static constexpr uint32_t kNoNodes = 0xffffffffu;
    double windowWeight(double distance) const;

    std::size_t wavelengthCount_ = 0;
    double radius_ = 0;  // R, scene units
    std::size_t pairCount_ = 0;
    // Per patch: its first node's index in nodes_ (15 nodes), or kNoNodes.
    std::vector<uint32_t> firstNode_;
    std::vector<float> nodes_;  // per node: Near (m values), then Omega
    std::vector<double> patchMeans_;  // N over the exposed lattice, n x m
    std::vector<double> coverage_;  // Omega_i, per patch
    std::vector<float> exposed_;  // phi per patch
    int channels_ = 0;
    std::vector<float> corners_;  // S per corner
    std::vector<float> emission_;  // E / pi per patch
    // The patches gathered exactly per sample (no nodes): per patch, its first neighbour in
    // exact_ (n + 1 entries; none for a lattice patch), and what the per-sample factor needs.
    struct ExactNeighbour {
        uint32_t patch;
        float visibility;
    };
    std::vector<uint32_t> firstExact_;
    std::vector<ExactNeighbour> exact_;
    std::vector<shared::PatchGeometry> geometry_;  // these three only when exact_ is not empty
    std::vector<shared::vec3> centroids_;
    std::vector<double> reflected_;  // (B_j - E_j) / phi_j, n x m
};

}  // namespace daisy
