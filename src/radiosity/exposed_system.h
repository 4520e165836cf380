#pragma once
// The radiosity system of the patches' exposed parts. A patch that runs
// under a block standing on it (radiosity/patch_exposure.h: phi_i, the share of its area that is
// not inside a closed object) gathers light only on its exposed part, but the plain system
// B = E + M F B spreads that light over the whole patch and sends it on at phi_i times its
// brightness: the buried share (1 - phi_i) of everything it reflects is lost, at every bounce.
// On the black-light box that was 4% of the emitted power ("escaped" through rows under 1 in a
// closed room) and made the indirect light 4-6% darker than the path tracer's.
//
// The exposed part (area phi_i A_i) sees what the patch sees, so its irradiance is
// G_i / phi_i, and neighbours see only it (F_ji already counts only the exposed part). Solving
//     B'_i = E_i + (s_i M_i) G_i,   G_i = sum_j F_ij B'_j,   s_i = 1 / max(phi_i, rowsum_i),
// for the exposed radiosity B' loses nothing: max(.., rowsum_i) keeps s_i F_i. from summing over
// 1 where the probe's 16 points under-estimate phi. The whole-patch mean the rest of the
// pipeline reads is then B_i = E_i + phi_i (B'_i - E_i), whose reflected part, divided by phi_i,
// gives the exposed value back exactly (image/near_field.h does that).
#include <cstdint>
#include <span>
#include <vector>

#include "radiosity/radiosity_system.h"
#include "radiosity/transport.h"

namespace daisy {

struct ExposedSystem {
    bool changed = false;  // some patch has 0 < phi < 1 and something to gather
    // The operators scaled by s_i (copies of the shared ones), and areas A_i / s_i, the area
    // the exposed value leaves from (the power norm and the energy bookkeeping use them).
    RadiositySystem system;
    std::vector<double> phi;  // per patch: phi_i where 0 < phi_i < 1, else 1 (no conversion)
    std::vector<double> rowSums;  // per patch: s_i rowsum_i, the rows of the exposed parts
};

// The exposed system for per-patch exposed shares `exposure` (in [0, 1]) and F's row sums.
// Patches with phi = 1, or nothing to gather, keep their operator; buried ones (phi = 0) reflect
// nothing (the inner faces of a closed double-sided object would otherwise pass light to and
// fro with the buried part of a patch under it, whose exposed scale 1 / phi amplifies it).
// Scales are rounded up to 1/64 of phi, so at most 64 copies of an operator are made.
ExposedSystem exposedSystem(const RadiositySystem& system, std::span<const float> exposure,
                            std::span<const double> rowSums);

// The transport's row sums without the factors into buried patches (phi_j = 0): the inside of
// a closed double-sided object is patches of its own, which a patch running under the object
// sees from its buried part, so its row sums to about 1 where a single-sided object's leaves
// phi_i. From the buried patches' own rows by reciprocity, F_ij = A_j F_ji / A_i.
std::vector<double> unburiedRowSums(const Transport& transport, std::span<const double> areas,
                                    std::span<const float> exposure);

// B = E + phi (B' - E) in place (n x m), and its inverse.
void exposedToWholePatch(const RadiositySystem& system, std::span<const double> phi,
                         std::span<double> radiosity);
void wholePatchToExposed(const RadiositySystem& system, std::span<const double> phi,
                         std::span<double> radiosity);

}  // namespace daisy
