#pragma once
// The widest x86 vector instruction set the CPU kernels may use: the hand-written lanes of the
// view-factor far field (radiosity/hybrid_far_field.h), the visibility sample generation
// (radiosity/visibility_samples.h), the solver's gather (radiosity/gather_kernels.h) and Embree's
// kernels (raycast/embree_ray_caster.cpp). The processor's widest by default; the environment
// variable DAISY_ISA=sse2|avx2|avx512 lowers it, so one machine can run the paths another
// machine would take (an AVX-512 machine checks its AVX2 paths: docs/backends.md). A value the
// processor lacks, or an unknown one, is a one-line warning and the processor's widest is used.
namespace daisy {

enum class CpuIsa { Sse2, Avx2, Avx512 };

// The ISA in effect (read once; thread-safe).
CpuIsa cpuIsa();

// The widest the processor runs, whatever DAISY_ISA says.
CpuIsa processorIsa();

// "sse2", "avx2" or "avx512".
const char* cpuIsaName(CpuIsa isa);

}  // namespace daisy
