#pragma once
// Links of the hierarchical transport (Hanrahan, Salzman and Aupperle 1991, "A rapid
// hierarchical radiosity algorithm", SIGGRAPH), made by refining node pairs of the cluster tree
// (hierarchical/cluster_tree.h) from the root's pair with itself.
//
// Two kinds of link:
// - near: a pair of patches, with the factors the matrix path would give them (the backend's
//   PairEvaluator: the view-factor kernel and its stratified shadow segments), the hybrid rule's
//   near cells refined to HierarchySettings::nearTolerance of each factor, stored as a sparse
//   matrix of F_ij over the patches;
// - far: a pair of nodes (R, S), each of whose patches faces every point of the other, with
//   the far-field coupling K = V c / (pi r^2): r the distance between their area-weighted
//   centroids, u the unit direction from R to S, V the share of shadow segments between
//   area-sampled points of R and S that get through, c the second-order correction for the
//   nodes' extent (their covariances, hierarchical_links.cpp). The irradiance a patch l of R
//   receives from S is then
//       G_l = (n_l . u) K (-u . P_S),   P_S = sum_{j in S} A_j n_j B_j,
//   exact for small nodes far apart (the point-to-point form factor with each patch's own
//   cosines: Cohen and Wallace 1993, "Radiosity and Realistic Image Synthesis", eq. 4.17), and
//   linear in B on both sides, so the link needs no cluster emission model beyond the patches'
//   own normals: the "vector" pull P and the push of J = sum K (-u . P_S) u (hierarchical_
//   transport.h). One link serves both directions (S receives K (u . P_R) along -u): reciprocity
//   A_R F_RS = A_S F_SR holds per link by construction. Between two planar nodes linked past
//   the far field's aperture (rho / d over maxAperture) or with the centroids' direction behind
//   a side, the link's weight K (u . n_R)(-u . n_S) is instead the mean of the segments' own
//   kernel, V cos cos / (pi r^2) (the oracle links such pairs only when their whole exchange
//   is within epsilon: link_oracle.h).
//
// The oracle, per candidate pair (R, S) with bounding spheres (c, rho) and normal cones:
// - a pair one of whose sides faces wholly away from the other exchanges nothing: no link;
// - power bound Phi = C (s_S y_R + s_R y_S): C = min(A_R, A_S, A_R A_S / (pi (d - rho)^2)),
//   d the distance of the sphere centres, rho the sum of the radii, s and y the nodes' largest
//   source and yield (hierarchical/link_oracle.h);
// - far link when the spheres are apart (d > rho), both sides wholly face each other, and the
//   far-field error bound Phi rho / d is at most epsilon = tolerance x the scene's visible
//   power; then, when Phi / 2 exceeds visibilityShare x epsilon, farRays / 2 segments between
//   the nodes' exposed parts decide: partly blocked, the pair is refined (partial visibility is
//   a reason to refine); else V comes from farRays / 2 more, independent of that decision; a
//   smaller pair's V from farRays / 4, or one segment when Phi <= visibilityShare x epsilon,
//   a pair that is kept by Russian roulette with probability Phi / (visibilityShare x
//   epsilon) and then carries its estimate over that probability; V = 0: no link;
// - otherwise the side with the larger sphere is split (a leaf never is); two patches become a
//   near link.
#include <cstdint>
#include <string_view>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "hierarchical/cluster_tree.h"
#include "hierarchical/link_oracle.h"
#include "radiosity/form_factors.h"
#include "radiosity/pair_evaluator.h"
#include "radiosity/patch_exposure.h"
#include "radiosity/sparse_matrix.h"
#include "raycast/ray_caster.h"

namespace daisy {

struct HierarchySettings {
    // epsilon relative to the scene's visible power (link_oracle.h); smaller: more links.
    double linkTolerance = 1e-6;
    // A partly visible far link is refined while half its power bound exceeds this share of
    // epsilon. Tighter than the far-field error because visibility errors do not average out
    // over a receiver's links: an occluder next to a patch (a lamp under a ceiling, a shelf)
    // biases every link of its node the same way. On the black-light box, 1 left the rendered
    // image 10% from the matrix path's (relative RMS luminance), 0.1 2.7%.
    double visibilityShare = 0.1;
    int farRays = 8;  // shadow segments per far link; fewer for one not refined for visibility
    // Largest rho / d of a far link (sphere radii over centre distance): bounds each patch's
    // relative error of the far-field coupling whatever the link's power.
    double maxAperture = 0.25;
    // The near links' hybrid rule refines its near cells to this share of each factor
    // (shared::hybridPairFactorWithin; F's own is DAISY_FF_REL_TOL, 3e-4). The far links'
    // errors are of the order of their aperture squared, and the final gather redoes the near
    // field per pixel: at 1e-2 the 30,012-triangle interior's near factors took 3.1 s instead of
    // 6.3 s and its picture moved by 0.01% (relative RMS luminance).
    float nearTolerance = 1e-2f;
};

// The direction u of a far link received by a node: the unit vector from the receiver's
// centroid to the source's (HierarchyNode::centroid).
inline Vec3d farDirection(const Vec3d& receiverCentroid, const Vec3d& sourceCentroid) {
    const Vec3d between = sourceCentroid - receiverCentroid;
    return between / length(between);
}

// Per node, the orientation the gather gives it: a leaf's patch normal, a planar inner node's
// cone axis (cluster_tree.h: every patch normal along it), zero for any other node, whose far
// links take the vector form (hierarchical_transport.h).
std::vector<Vec3d> gatherOrientations(const ClusterTree& tree, const std::vector<Vec3d>& normals);
// Per node, where its pull values start in units of m (1 slot a planar node, 3 another), and
// the end after the last node.
std::vector<uint64_t> gatherSlots(const std::vector<Vec3d>& orientations);

// The far half-links by receiving node, in the form the gather applies them (farGather):
// between two planar nodes, the source's slot (where its pull values start, in units of m)
// and the weight -K (u . n_S) (u . n_R); the others with their direction folded into one
// vector (OtherLink). The build makes them in this form from its records, and the transport keeps
// them so: a list of (source, K) per half-link beside it was as large again (1.95 of the 4.38 GiB
// of the 250,002-triangle interior's transport).
struct FarHalfLinks {
    static constexpr uint32_t kPlanarSource = 1u << 31;
    struct OtherLink {
        uint32_t slot;  // the source's slot, kPlanarSource set when the source is planar
        // A planar source's scalar Q_S gives J += Q_S v with v = -K (u . n_S) u; a planar
        // receiver's n_R . J takes v . P_S with v = -K (u . n_R) u; between two other nodes
        // J += -(v . P_S) v with v = sqrt(K) u.
        float v[3];

        uint32_t source() const { return slot & ~kPlanarSource; }  // the source's slot
        bool planarSource() const { return (slot & kPlanarSource) != 0; }
    };
    std::vector<uint64_t> planarOffsets, otherOffsets;  // per node + 1
    std::vector<uint32_t> planarSlots;
    std::vector<float> planarWeights;
    std::vector<OtherLink> others;

    uint64_t count() const { return planarSlots.size() + others.size(); }
    uint64_t count(std::size_t node) const {
        return planarOffsets[node + 1] - planarOffsets[node] + otherOffsets[node + 1] -
            otherOffsets[node];
    }
    uint64_t bytes() const;
};

struct LinkStats {
    uint64_t nearEntries = 0;  // stored F_ij of the near links (both directions)
    uint64_t farLinks = 0;  // node pairs (unordered)
    uint64_t candidates = 0;  // node pairs the oracle examined
    uint64_t facingAway = 0;  // pairs dropped: one side faces wholly away
    uint64_t hidden = 0;  // far pairs dropped: no segment got through
    uint64_t partlyVisibleRefined = 0;  // far pairs refined for partial visibility
    uint64_t rouletteDropped = 0;  // far pairs within the visibility share left out by roulette
    uint64_t raysCast = 0;  // far links' segments (the near links' are the evaluator's)
    uint64_t nearPairsEvaluated = 0;  // patch pairs handed to the evaluator
    double refineSeconds = 0;
    double nearSeconds = 0;
};

struct HierarchicalLinks {
    SparseMatrix near;  // F_ij of the near links, patch rows
    FarHalfLinks far;  // by receiving node, sources ascending
    LinkStats stats;
};

// What the refinement records per link before the links take their final form: a far link's
// nodes and coupling, a near link's patch pair.
inline constexpr uint64_t kFarRecordBytes = 12;
inline constexpr uint64_t kNearRecordBytes = 8;
// How the error of a build stopped by its record limit begins.
inline constexpr std::string_view kLinkRecordsOverLimit = "the links' records passed ";

// Refines the root's pair with itself; near pairs evaluated by `evaluator` with
// settings.raysPerPair segments, far links' visibility by `rays` between the patches' exposed
// parts (`exposure`, of the same patches). Deterministic (any thread count). Errors: the
// evaluator's, the cancel token's kInterruptedMessage, or, once the records (kFarRecordBytes a
// far link, kNearRecordBytes a near pair) pass `recordLimitBytes`, kLinkRecordsOverLimit with
// the limit and the counts reached: the refinement stops there, before the records are copied.
Expected<HierarchicalLinks> buildHierarchicalLinks(const PatchMesh& mesh, const ClusterTree& tree,
                                                   const PatchExposure& exposure,
                                                   const LinkImportance& importance,
                                                   const HierarchySettings& hierarchy,
                                                   const FormFactorSettings& settings,
                                                   PairEvaluator& evaluator, const RayCaster& rays,
                                                   uint64_t recordLimitBytes = UINT64_MAX);

}  // namespace daisy
