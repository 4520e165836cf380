#pragma once
// Helpers the form-factor drivers share (form_factors.cpp, stochastic_form_factors.cpp); not a
// public interface.
#include <cstdint>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "radiosity/form_factors.h"
#include "shared/gpu_types.h"

namespace daisy::detail {

// The DAISY_METHOD_* constant the shared kernels take.
int methodConstant(FormFactorMethod method);

// The 32-bit seed of the shared sample sequences from the 64-bit --seed.
uint32_t seed32(uint64_t seed);

// Kernel geometry: float corners, with normal and area from the double-precision mesh.
std::vector<shared::PatchGeometry> kernelGeometry(const PatchMesh& mesh);

// The stochastic method (computeFormFactors dispatches here), inside the caller's task arena.
Expected<FormFactorResult> computeStochastic(const PatchMesh& mesh,
                                             const FormFactorSettings& settings,
                                             const RayCaster& rays);

}  // namespace daisy::detail
