#pragma once
// What the refinement oracle (hierarchical/hierarchical_links.h) knows of the light before the
// solve: per patch, how much visible light it can send (`source`) and how much of the light it
// receives can become visible (`yield`). Spectral and fluorescence-aware: every wavelength
// sample, UV included, is weighed by the visible light it can become.
//
// Weights. ybar_o is the CIE 1931 luminance function at sample o, scaled to a maximum of 1. A
// material operator M turns irradiance at sample k into visible exitance
//     Y_op(k) = sum_o M[o][k] ybar_o w_o / w_k            (w: bin widths),
// and light at k is worth W_k = max(ybar_k, max over fluorescent operators of Y_op(k)): seen
// directly, or after one fluorescent bounce (so a white wall's reflected UV, which a poster can
// turn into visible light, counts as much as that poster would make of it).
//
// The light before the solve: the emission plus one bounce of an ambient irradiance (Cohen,
// Chen, Wallace and Greenberg 1988, "A progressive refinement approach to fast radiosity image
// generation", SIGGRAPH, section 4.2): Gbar_k = (sum_i A_i E_ik / sum_i A_i) / (1 - rhobar_k),
// rhobar the area-weighted mean reflectance, capped at 0.95. The emission counts only by the
// share that comes back as indirect light, r = sum_k rhobar_k W_k w_k / sum_k W_k w_k: the
// image's final gather recomputes the emitters' direct light per pixel, so the links carry the
// smooth indirect light and need not resolve the direct light patch by patch. Then
//     source_j = sum_k (r E_jk + (M_j Gbar)_k) W_k w_k      (visible-weighted exitance, W m^-2)
//     yield_j  = max_k (sum_o M_j[o][k] W_o w_o) / (W_k w_k), clamped to [0, 1].
// The ambient light only reaches patches that light can reach: a patch of a region with no
// emitter (`lit`, hierarchical_transport.cpp: the regions of patches joined by survey rays) has
// source 0, and a pair of such patches carries nothing; a patch of a closed region with no
// emitter (`dark`: the inside of a closed double-sided box standing on the floor) has yield 0
// as well, so it carries nothing with any patch.
#include <cstdint>
#include <span>
#include <vector>

#include "hierarchical/cluster_tree.h"
#include "radiosity/radiosity_system.h"

namespace daisy {

struct LinkImportance {
    std::vector<double> source;  // per patch, W m^-2 of visible-weighted exitance
    std::vector<double> yield;  // per patch, dimensionless in [0, 1]
    double totalPower = 0;  // sum_j A_j source_j, W (scene units squared x W m^-2)
};

// lit: per patch, 0 when no light can reach it (empty: every patch can); dark: per patch, 1
// when it can receive none either (empty: none is).
LinkImportance linkImportance(const RadiositySystem& system, std::span<const uint8_t> lit = {},
                              std::span<const uint8_t> dark = {});

// Whether links refined for `before` may carry more error than the oracle allows under `after`
// (the same patches, after an edit of materials or lights): some patch's share of the scene's
// visible power (source / totalPower), or its yield, grew past `factor` times what it was (a
// share from 0 to anything: a new emitter, or a black material made grey). A far link's bound
// is the product of a source and a yield over epsilon, which is proportional to the total
// power, so under a growth below the factor every link stays within factor^2 of epsilon. A
// uniform change of every light's strength changes no share.
bool importanceGrew(const LinkImportance& before, const LinkImportance& after, double factor);

// The oracle's geometric decision for two distinct nodes R and S, before visibility
// (hierarchical/hierarchical_links.h gives the rules): no exchange (one side faces wholly away,
// or the pair carries nothing: s_S y_R + s_R y_S = 0), a far link, or a split of R or of S, or a
// near link (two leaves).
enum class LinkChoice { None, Far, SplitReceiver, SplitSource, Near };

struct LinkWeights {
    double sourceR = 0, yieldR = 0;  // R's largest source and yield
    double sourceS = 0, yieldS = 0;
};

// A far link's estimate of a pair's exchange is at most this times the pair's power bound Phi:
// its coupling K = V c / (pi r^2) has c <= 1.5 and r, the distance of the centroids, at least
// the gap d - rho between the spheres, and K is capped at 1 / max(A_R, A_S)
// (hierarchical_links.cpp), so K A_R A_S <= 1.5 min(A_R, A_S, A_R A_S / (pi (d - rho)^2)).
inline constexpr double kFarEstimateBound = 1.5;

struct LinkDecision {
    LinkChoice choice = LinkChoice::Near;
    // The power bound Phi (W), 0 when the spheres overlap; the bound on a far link's error:
    // Phi rho / d (the far field's), or kFarEstimateBound Phi for a pair linked because its
    // whole exchange is within epsilon (at any aperture, or facing the other only in part).
    double power = 0;
    double error = 0;
};

// When a pair is not linked: split the side with the larger bounding sphere (never a leaf), or
// Near for two leaves.
LinkChoice splitChoice(const HierarchyNode& r, const HierarchyNode& s);

// epsilon: the largest error bound a far link may have (W); maxAperture: the largest rho / d.
LinkDecision chooseLink(const HierarchyNode& r, const HierarchyNode& s, const LinkWeights& weights,
                        double epsilon, double maxAperture);

}  // namespace daisy
