#pragma once
// Energy bookkeeping of a solved radiosity system (DESIGN.md section 6). Powers are in watts
// per unit of the scene's emission scale: P(X) = sum_i A_i sum_k w_k X_ik, A_i the patch area,
// w_k the wavelength set's bin width (nm), X a spectral exitance (W m^-2 nm^-1).
//
// With G_i = sum_j F_ij B_j the irradiance arriving at patch i (by reciprocity
// A_i F_ij = A_j F_ji, P(G) is the power arriving at patches), in steady state
//     emitted = absorbed + escaped,
//     absorbed = P(G) - reflected - converted   (includes the Stokes and quantum-yield losses),
//     escaped  = sum_i A_i (1 - rowsum_i) sum_k w_k B_ik   (through openings),
//     reflected = P of diag(M) G,  converted = P of the off-diagonal part of M G (fluorescence:
//     power re-emitted at longer wavelengths).
// The balance closes to the solve's residual plus F's departure from reciprocity.
#include <span>
#include <vector>

#include "radiosity/radiosity_system.h"
#include "radiosity/sparse_matrix.h"

namespace daisy {

struct EnergyBalance {
    double emitted = 0;
    double incident = 0;  // P(G): power arriving at patches
    double reflected = 0;
    double converted = 0;  // re-emitted by fluorescence at another wavelength
    double absorbed = 0;
    double escaped = 0;
    std::vector<double> emittedPerSample;  // A_i E_ik w_k summed over patches, per sample k
    std::vector<double> escapedPerSample;
    std::vector<double> absorbedPerSample;  // incident - reflected - converted-away, per sample
    std::vector<double> convertedInPerSample;  // fluorescent power arriving in sample k
    // (emitted - absorbed - escaped) / emitted; 0 when nothing is emitted.
    double imbalance() const;
};

// The bookkeeping for radiosity B and its gather G = F B (both patchCount x m), with F's row
// sums (rowSums(F)).
EnergyBalance computeEnergyBalance(const RadiositySystem& system, std::span<const double> rowSums,
                                   std::span<const double> radiosity,
                                   std::span<const double> gathered);

}  // namespace daisy
