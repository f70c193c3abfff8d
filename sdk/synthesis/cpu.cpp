#include "synthesis/cpu.hpp"

#include <cstdlib>
#include <cstring>

namespace ssc::kernels {

Isa supported_isa() {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
    // libgcc's CPU-feature word, filled at start-up; it also checks that the OS saves the wider
    // registers (XSAVE state), so a CPU with AVX under an OS without it reports none.
    if (__builtin_cpu_supports("avx512f")) return Isa::Avx512;
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return Isa::Avx2;
#endif
    return Isa::Baseline;
}

Isa active_isa() {
    static const Isa isa = [] {
        Isa best = supported_isa();
        if (const char* want = std::getenv("SSCAPE_ISA")) {
            Isa cap = best;
            if (std::strcmp(want, "baseline") == 0) cap = Isa::Baseline;
            else if (std::strcmp(want, "avx2") == 0) cap = Isa::Avx2;
            if (int(cap) < int(best)) best = cap;
        }
        return best;
    }();
    return isa;
}

const char* isa_name(Isa isa) {
    switch (isa) {
        case Isa::Baseline: return "baseline";
        case Isa::Avx2: return "avx2";
        case Isa::Avx512: return "avx512";
    }
    return "baseline";
}

}  // namespace ssc::kernels
