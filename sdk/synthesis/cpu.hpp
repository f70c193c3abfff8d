// Which instruction sets the hand-written kernels use.
//
// The library is compiled for plain x86-64, so it runs on any x86-64 CPU. The kernels that pay for
// wider vectors (shape, rest joints, skinning; the fitter's normal-equation products) also come
// compiled for AVX2 + FMA (the shape for AVX-512 too), and each call takes the widest one that the
// CPU and the operating system support. The synthesis paths give the same bits (they fix the order
// of their fused multiply-adds), so there the choice changes speed, never results; the fitter's
// baseline product is Eigen's, whose sums round differently in the last bits.
//
// SSCAPE_ISA=baseline|avx2|avx512 in the environment lowers the choice for the whole process (it
// never raises it past what the CPU supports): for tests of the fallback paths, and to time them.
#pragma once

// Everything between SSC_TARGET_AVX2_BEGIN (or SSC_TARGET_AVX512_BEGIN) and SSC_TARGET_END
// (functions, templates, lambdas) is compiled for AVX2 + FMA (and AVX-512F); callers check
// active_isa() first. GCC and clang spell it differently.
#if defined(__clang__)
#define SSC_TARGET_AVX2_BEGIN _Pragma("clang attribute push (__attribute__((target(\"avx2,fma\"))), apply_to = function)")
#define SSC_TARGET_AVX512_BEGIN _Pragma("clang attribute push (__attribute__((target(\"avx2,fma,avx512f\"))), apply_to = function)")
#define SSC_TARGET_END _Pragma("clang attribute pop")
#else
#define SSC_TARGET_AVX2_BEGIN _Pragma("GCC push_options") _Pragma("GCC target(\"avx2,fma\")")
#define SSC_TARGET_AVX512_BEGIN _Pragma("GCC push_options") _Pragma("GCC target(\"avx2,fma,avx512f\")")
#define SSC_TARGET_END _Pragma("GCC pop_options")
#endif

namespace ssc::kernels {

enum class Isa { Baseline = 0, Avx2 = 1, Avx512 = 2 };

// The widest set this CPU and OS support.
Isa supported_isa();
// supported_isa() lowered by SSCAPE_ISA; read once, on first use, then fixed for the process.
Isa active_isa();
// "baseline", "avx2" or "avx512".
const char* isa_name(Isa isa);

}  // namespace ssc::kernels
