#pragma once
// The hierarchical transport (Transport, radiosity/transport.h): links between nodes of a
// cluster tree over the patches instead of the all-pairs matrix F, so memory and time grow
// about linearly with the scene (hierarchical/hierarchical_links.h for the links and the
// oracle that makes them, hierarchical/cluster_tree.h for the tree).
//
// G = T B, for B (n x m): the near links' sparse F B, plus the far links by push-pull:
//   pull  P_k = sum over the patches j below node k of A_j phi_j n_j B_j (3 m values a node,
//         children summed into parents; phi: the exposed share, below);
//   link  J_R = sum over R's far links (S, K, u) of K (-u . P_S) u;
//   push  J of every node added into its children's, and G_l += phi_l n_l . J_l at each patch l.
// A planar node (every patch normal n, cluster_tree.h) holds the scalar form instead, m values:
// Q = sum A_j phi_j B_j (P = n Q) and n . J, which its patches receive unchanged. Most links
// join two planar nodes and then cost one product a wavelength, like an entry of F.
// Row sums: a patch whose kEnclosureRays cosine rays all land on the front of other patches
// (hierarchical_transport.cpp, surveyPatches) is enclosed, and its factors must sum to 1 (every
// ray leaving it lands on a patch): its far part is scaled so that the row sums to exactly 1,
// which removes the far field's and the hidden links' share of error from the sum (the white
// furnace then holds exactly); in an open region only when its links sum to within kOpenFill
// of 1 (it may see an opening its rays missed). Other rows whose factors sum past 1 are capped at 1
// the same way, as the matrix path caps F's rows (capRowSums). The near factors are F's own and
// stay; only a row whose near part alone passes 1 is scaled as a whole.
//
// Exposed parts (radiosity/patch_exposure.h): the far links couple the patches' exposed parts,
// so a patch's far light is weighed by its exposed share phi on both ends, pulled as
// A_j phi_j B_j and pushed as phi_l n_l . J_l, which is what F's entries hold (its rays from a
// buried point are blocked): F_ij ~ phi_i phi_j times the exposed parts' factor, patch by
// patch, also inside a node whose patches are buried to different depths.
//
// The patches stay the radiosity patches: every front end (vertex radiance, the final gather,
// the viewer) works on them unchanged; row(i) gives the near links, the patches close enough
// to i to need their own factors, which is what the near-field gather asks for.
#include <memory>
#include <mutex>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "hierarchical/cluster_tree.h"
#include "hierarchical/hierarchical_links.h"
#include "radiosity/radiosity_system.h"
#include "radiosity/transport.h"

namespace daisy {

inline constexpr int kEnclosureRays = 32;

// Per patch, what the constructor's `enclosed` says of its row (0: nothing, capped at 1 only).
inline constexpr uint8_t kEnclosed = 1;  // in a closed region: filled to exactly 1
inline constexpr uint8_t kEnclosedInOpenRegion = 2;  // filled when within kOpenFill of 1
// In an open region, an enclosed patch's row is filled to 1 when its links sum to at least
// 1 - kOpenFill: the far field's noise, which the caps alone turn into a loss (a row over 1 is
// capped, one under it kept). On the 30,012-triangle interior, whose one region is open, 26%
// of the patches' area had rows over 1 before the caps (by 2.8% on average), and the picture
// was 7.55% from the path tracer's and 4.1% dark; filled within 0.05, 7.04% and 3.1% dark. A
// wider margin fills more of its rows (0.1: 6.79%, unbounded: 6.15%), but also the rows of
// patches that see the open front of the Cornell box, whose patch radiosity then passes 1% from
// the matrix path's (0.87% within 0.05, 1.01% within 0.1); its error against the path tracer
// moves by 0.02% either way.
inline constexpr double kOpenFill = 0.05;

// What the disk cache keeps of a built transport (pipeline/links_cache.h): enough to restore
// it exactly, the near factors and the far scales as the row caps left them.
struct HierarchicalParts {
    ClusterTree tree;
    SparseMatrix near;
    LinkStats stats;
    FarHalfLinks far;
    std::vector<double> farScale;  // per patch
    std::vector<double> rowSums;  // per patch
    std::vector<float> exposure;  // per patch: phi, the exposed share
};

class HierarchicalTransport final : public Transport {
public:
    // exposure: per patch, phi (PatchExposure::fraction); enclosed: per patch, kEnclosed,
    // kEnclosedInOpenRegion or 0 (empty: no patch known to be enclosed).
    HierarchicalTransport(const PatchMesh& mesh, ClusterTree tree, HierarchicalLinks links,
                          std::vector<float> exposure, const std::vector<uint8_t>& enclosed = {});
    // Restores a transport from the parts of one built for the same patches (the links cache
    // stores them; checkStructure() tells whether they hold together).
    HierarchicalTransport(const PatchMesh& mesh, HierarchicalParts parts);

    const char* kind() const override { return "hierarchical"; }
    uint32_t patchCount() const override { return near_.size; }
    TransportStats stats() const override;
    std::span<const double> rowSums() const override { return rowSums_; }
    std::string checkStructure() const override;
    void gather(std::span<const double> radiosity, std::size_t wavelengthCount,
                std::span<double> gathered, int threads = 0) const override;
    void gatherFrom(std::span<const uint8_t> sources, std::span<const uint8_t> receivers,
                    std::span<const double> radiosity, std::size_t wavelengthCount,
                    std::span<double> gathered) const override;
    void row(uint32_t patch, std::vector<TransportEntry>& out) const override;
    Expected<SolverResult> solve(const RadiositySystem& system,
                                 SolverSettings settings) const override;
    Expected<void> writeMatrixMarket(const std::string& path,
                                     const std::vector<std::string>& comments) const override;
    Expected<MatrixComparison> compare(const Transport& other,
                                       const MatrixCompareSettings& settings) const override;

    const ClusterTree& tree() const { return tree_; }
    const SparseMatrix& near() const { return near_; }  // the near links' F_ij
    const LinkStats& linkStats() const { return stats_; }
    const FarHalfLinks& farLinks() const { return far_; }
    // Per node: where its pull values start (units of m), and the end after the last node.
    const std::vector<uint64_t>& slots() const { return slot_; }
    const std::vector<double>& farScale() const { return farScale_; }
    const std::vector<float>& exposure() const { return exposure_; }
    // The far links' part of G = T B (n x m, overwritten), rows capped as the near part.
    // sourceSlots: per slot (slots()), whether a node has a source below it; the others' B is
    // taken as 0 (not read) and the links from them are skipped (empty: every node has).
    void farGather(std::span<const double> radiosity, std::size_t wavelengthCount,
                   std::span<double> gathered, std::span<const uint8_t> sourceSlots = {}) const;

private:
    // The per-node arrays the gather reads (a valid tree).
    void prepareNodes();
    // checkStructure's part on the tree and the per-patch arrays.
    std::string checkTree() const;
    // Per node: its normal when it is planar (every leaf is), else zero.
    bool isPlanar(std::size_t node) const { return orientation_[node] != Vec3d{}; }

    ClusterTree tree_;
    SparseMatrix near_;
    LinkStats stats_;
    FarHalfLinks far_;
    std::vector<Vec3d> normals_;  // per patch
    std::vector<double> areas_;  // per patch
    std::vector<float> exposure_;  // per patch: phi
    std::vector<Vec3d> orientation_;  // per node: see isPlanar
    std::vector<uint64_t> slot_;  // per node: its far-gather values start at slot_ x m; + end
    // The far gather's pull (float: the links read it at random, so its size is their memory
    // traffic) and push values, reused by one gather at a time (another concurrent one
    // allocates its own).
    mutable std::mutex workspaceMutex_;
    mutable std::vector<float> pullWorkspace_;
    mutable std::vector<double> pushWorkspace_;
    std::vector<double> farScale_;  // per patch: the row cap's scale of the far part (1: none)
    std::vector<double> rowSums_;
};

// What the transport will hold before it is built, for --max-memory and `daisy info`: the tree,
// links at the rates measured on the generator's interiors, the Blender-style box and the
// default scene (growing slowly with the patches), and a gather's work arrays (the pull and
// push values, 3 m floats and 3 m doubles a node); and what building it holds at its peak.
// Scenes differ by four times in links a patch, so the estimate is a range: at the highest rates
// measured (what the build is expected to need at most) and at the lowest (what it needs at
// least). --max-memory refuses a build before it starts when the least passes it; otherwise
// the build itself stops once its records would pass it (linkRecordLimit).
struct HierarchyEstimate {
    uint64_t nearEntries = 0;  // at the highest rates
    uint64_t farLinks = 0;
    uint64_t bytes = 0;  // held by the built transport
    uint64_t peakBytes = 0;  // the larger of bytes and the build's link records with their copies
    uint64_t leastPeakBytes = 0;  // the build's peak at the lowest rates measured
};
HierarchyEstimate estimateHierarchy(const PatchMesh& mesh, std::size_t wavelengthCount);

// What the link records (hierarchical_links.h) may hold when the build may hold `maxBytes`:
// the estimate's peak is the tree's arrays and the records three times over (a thread's grown
// vector up to twice its records, and their merged copy), so a third of what the tree leaves.
uint64_t linkRecordLimit(const PatchMesh& mesh, std::size_t wavelengthCount, uint64_t maxBytes);

// Builds the tree and the links on the CPU (Embree rays, TBB threads): the oracle weighs the
// light of `system` (hierarchical/link_oracle.h), the near links are the cpu backend's pair
// evaluation with `settings` (method, L, K, seed, threads, cancel), the far links' visibility
// is sampled on the patches' exposed parts (`exposure`: patchExposure(mesh)). The refinement
// stops with buildHierarchicalLinks's kLinkRecordsOverLimit error once its records pass
// linkRecordLimit(maxBytes).
Expected<std::shared_ptr<const HierarchicalTransport>> buildHierarchicalTransport(
    const PatchMesh& mesh, const PatchExposure& exposure, const RadiositySystem& system,
    const HierarchySettings& hierarchy, const FormFactorSettings& settings,
    uint64_t maxBytes = UINT64_MAX);

}  // namespace daisy
