#include "core/cpu_isa.h"

#include <cstdlib>
#include <string>

#include "core/log.h"

namespace daisy {
// AVX-512 (F) and AVX2 with FMA are what the kernels' variants are compiled for.
CpuIsa processorIsa() {
#if defined(__x86_64__) && defined(__GNUC__)
    if (__builtin_cpu_supports("avx512f")) return CpuIsa::Avx512;
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return CpuIsa::Avx2;
#endif
    return CpuIsa::Sse2;
}

namespace {

CpuIsa chooseIsa() {
    const CpuIsa widest = processorIsa();
    const char* value = std::getenv("DAISY_ISA");
    if (value == nullptr || *value == '\0') return widest;
    const std::string name = value;
    for (CpuIsa isa : {CpuIsa::Sse2, CpuIsa::Avx2, CpuIsa::Avx512}) {
        if (name != cpuIsaName(isa)) continue;
        if (isa > widest) {
            logWarning("DAISY_ISA=" + name + ": this processor runs at most " + cpuIsaName(widest) +
                       "; using " + cpuIsaName(widest));
            return widest;
        }
        return isa;
    }
    logWarning("DAISY_ISA=" + name + " is not one of sse2, avx2, avx512; using " +
               cpuIsaName(widest));
    return widest;
}

}  // namespace

CpuIsa cpuIsa() {
    static const CpuIsa isa = chooseIsa();
    return isa;
}

const char* cpuIsaName(CpuIsa isa) {
    switch (isa) {
        case CpuIsa::Sse2:
            return "sse2";
        case CpuIsa::Avx2:
            return "avx2";
        case CpuIsa::Avx512:
            return "avx512";
    }
    return "?";
}

}  // namespace daisy
