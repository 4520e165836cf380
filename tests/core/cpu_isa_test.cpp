// The instruction-set switch (core/cpu_isa.h): DAISY_ISA lowers the ISA the kernels use, never
// above what the processor runs. ctest runs the kernels' and the view factors' tests again with
// DAISY_ISA=avx2 and =sse2 (tests/CMakeLists.txt), and this test checks there that the switch
// took effect.
#include "core/cpu_isa.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace daisy {
namespace {

TEST(CpuIsa, FollowsDaisyIsaUpToTheProcessor) {
    const char* value = std::getenv("DAISY_ISA");
    const std::string asked = value ? value : "";
    CpuIsa expected = processorIsa();
    for (CpuIsa isa : {CpuIsa::Sse2, CpuIsa::Avx2, CpuIsa::Avx512}) {
        if (asked == cpuIsaName(isa) && isa < expected) expected = isa;
    }
    EXPECT_EQ(cpuIsaName(cpuIsa()), std::string(cpuIsaName(expected))) << "DAISY_ISA=" << asked;
}

}  // namespace
}  // namespace daisy
