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
// rhobar the area-weighted mean reflectance, capped at 0.95. Then
//     source_j = sum_k (E_jk + (M_j Gbar)_k) W_k w_k        (visible-weighted exitance, W m^-2)
//     yield_j  = max_k (sum_o M_j[o][k] W_o w_o) / (W_k w_k), clamped to [0, 1].
#include <vector>

#include "radiosity/radiosity_system.h"

namespace daisy {

struct LinkImportance {
    std::vector<double> source;  // per patch, W m^-2 of visible-weighted exitance
    std::vector<double> yield;  // per patch, dimensionless in [0, 1]
    double totalPower = 0;  // sum_j A_j source_j, W (scene units squared x W m^-2)
};

LinkImportance linkImportance(const RadiositySystem& system);

}  // namespace daisy
