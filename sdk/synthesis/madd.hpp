// a * b + c as the synthesis kernels compute it: fused, rounded once, on every native path (one
// instruction with FMA, exact in libm without), so AVX2, AVX-512 and baseline x86-64 give the same
// bits. WebAssembly has no fused multiply-add and libm's exact one is done in software there, many
// times slower, so the browser runtime rounds twice (docs/web.md, "Same bits?").
#pragma once

#include <cmath>

namespace ssc::kernels {

[[gnu::always_inline]] inline float madd(float a, float b, float c) {
#if defined(__wasm__)
    return a * b + c;
#else
    return std::fma(a, b, c);
#endif
}

}  // namespace ssc::kernels
