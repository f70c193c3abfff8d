// Shape stage: rest = mean + sum_k (c_k * step_k) * q_k over the 16-bit basis.
//
// Every output value is accumulated as acc = fma(c_k * step_k, q_k, acc) for k = 0, 1, ... in
// that order, whatever the vector width or blocking; so one body and a batch, and the AVX2 and
// AVX-512 paths, give bit-identical results.
//
// Cost model: the basis is 4 MB for the default-size model, more than L2, so one body is bound by
// the bandwidth of streaming it from L3. The panel layout (model.hpp) makes that one sequential
// stream. A batch tiles bodies so each basis panel, once loaded, feeds several bodies'
// accumulators held in registers, which makes it FMA-bound instead; AVX-512, where the CPU has it
// (chosen at run time), doubles that throughput.
//
// The library is compiled for plain x86-64; the AVX2 and AVX-512 kernels are compiled for their
// instruction sets by target pragmas and chosen per call (cpu.hpp).
#include "cpu.hpp"
#include "kernels.hpp"
#include "madd.hpp"
#include "model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#include <immintrin.h>
#define SSC_SHAPE_AVX2 1
#define SSC_SHAPE_AVX512 1
#endif
#if defined(__wasm_simd128__)
#include <wasm_simd128.h>
#endif

namespace ssc::kernels {
namespace {

constexpr std::size_t kChunk = Model::kChunk;  // rows per panel

#ifdef SSC_SHAPE_AVX2
SSC_TARGET_AVX2_BEGIN
// G bodies x P panels of 16 rows (2 ymm each) starting at panel `first`.
template <int G, int P>
void tile_avx2(const Model& m, std::size_t first, const float* const* scaled, float* const* rest) {
    const uint32_t K = m.component_count();
    const std::size_t r = first * kChunk;
    const int16_t* panel = m.basis_panels() + first * K * kChunk;
    constexpr int H = 2 * P;  // 8-row halves
    const float* sg[G];
    __m256 acc[G][H];
    for (int g = 0; g < G; ++g) sg[g] = scaled[g];
    for (int h = 0; h < H; ++h) {
        const __m256 mean = _mm256_loadu_ps(m.mean_planar() + r + 8 * h);
        for (int g = 0; g < G; ++g) acc[g][h] = mean;
    }
    for (uint32_t k = 0; k < K; ++k) {
        __m256 b[H];
        for (int h = 0; h < H; ++h) {
            const auto* p = reinterpret_cast<const __m128i*>(panel + ((h / 2) * K + k) * kChunk + 8 * (h % 2));
            b[h] = _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(_mm_loadu_si128(p)));
        }
        for (int g = 0; g < G; ++g) {
            const __m256 cg = _mm256_broadcast_ss(sg[g] + k);
            for (int h = 0; h < H; ++h) acc[g][h] = _mm256_fmadd_ps(cg, b[h], acc[g][h]);
        }
    }
    for (int g = 0; g < G; ++g)
        for (int h = 0; h < H; ++h) _mm256_storeu_ps(rest[g] + r + 8 * h, acc[g][h]);
}

template <int G, int P>
void pass_avx2(const Model& m, const float* const* scaled, float* const* rest, std::size_t first, std::size_t end) {
    std::size_t c = first;
    for (; c + P <= end; c += P) tile_avx2<G, P>(m, c, scaled, rest);
    for (; c < end; ++c) tile_avx2<G, 1>(m, c, scaled, rest);
}

void shape_avx2(const Model& m, std::size_t count, const float* const* scaled, float* const* rest, std::size_t first, std::size_t end) {
    for (std::size_t g = 0; g < count;) {
        const std::size_t left = count - g;
        if (left >= 4) pass_avx2<4, 1>(m, scaled + g, rest + g, first, end), g += 4;
        else if (left >= 2) pass_avx2<2, 2>(m, scaled + g, rest + g, first, end), g += 2;
        else pass_avx2<1, 4>(m, scaled + g, rest + g, first, end), g += 1;
    }
}
SSC_TARGET_END
#endif

#ifdef SSC_SHAPE_AVX512
#define SSC_AVX512 __attribute__((target("avx2,fma,avx512f")))

template <int G, int P>
SSC_AVX512 void tile_avx512(const Model& m, std::size_t first, const float* const* scaled, float* const* rest) {
    const uint32_t K = m.component_count();
    const std::size_t r = first * kChunk;
    const int16_t* panel = m.basis_panels() + first * K * kChunk;
    const float* sg[G];
    __m512 acc[G][P];
    for (int g = 0; g < G; ++g) sg[g] = scaled[g];
    for (int p = 0; p < P; ++p) {
        const __m512 mean = _mm512_loadu_ps(m.mean_planar() + r + kChunk * p);
        for (int g = 0; g < G; ++g) acc[g][p] = mean;
    }
    for (uint32_t k = 0; k < K; ++k) {
        __m512 b[P];
        for (int p = 0; p < P; ++p) {
            const auto* q = reinterpret_cast<const __m256i*>(panel + (p * K + k) * kChunk);
            // maskz forms with a full mask: same instructions, and no GCC 12 false
            // -Wmaybe-uninitialized from the unmasked intrinsics' undefined source operand.
            b[p] = _mm512_maskz_cvtepi32_ps(0xFFFF, _mm512_maskz_cvtepi16_epi32(0xFFFF, _mm256_loadu_si256(q)));
        }
        for (int g = 0; g < G; ++g) {
            const __m512 cg = _mm512_set1_ps(sg[g][k]);
            for (int p = 0; p < P; ++p) acc[g][p] = _mm512_fmadd_ps(cg, b[p], acc[g][p]);
        }
    }
    for (int g = 0; g < G; ++g)
        for (int p = 0; p < P; ++p) _mm512_storeu_ps(rest[g] + r + kChunk * p, acc[g][p]);
}

template <int G, int P>
SSC_AVX512 void pass_avx512(const Model& m, const float* const* scaled, float* const* rest, std::size_t first, std::size_t end) {
    std::size_t c = first;
    for (; c + P <= end; c += P) tile_avx512<G, P>(m, c, scaled, rest);
    for (; c < end; ++c) tile_avx512<G, 1>(m, c, scaled, rest);
}

SSC_AVX512 void shape_avx512(const Model& m, std::size_t count, const float* const* scaled, float* const* rest, std::size_t first,
                             std::size_t end) {
    for (std::size_t g = 0; g < count;) {
        const std::size_t left = count - g;
        if (left >= 8) pass_avx512<8, 2>(m, scaled + g, rest + g, first, end), g += 8;
        else if (left >= 4) pass_avx512<4, 2>(m, scaled + g, rest + g, first, end), g += 4;
        else if (left >= 2) pass_avx512<2, 4>(m, scaled + g, rest + g, first, end), g += 2;
        else pass_avx512<1, 8>(m, scaled + g, rest + g, first, end), g += 1;
    }
}

#endif

#if defined(__wasm_simd128__)
// WebAssembly SIMD (the browser runtime). WebAssembly has no fused multiply-add (std::fma is done in
// software there, many times slower), so each step is a multiply and an add, rounded twice: the rest
// vertices differ from the native library's by an ulp or so (docs/web.md, "Same bits?").
// One panel: its 16 int16 rows of component k are two 128-bit loads; each 32-bit lane holds rows 2i
// and 2i+1, moved into the high half (even rows: a shift) or masked there (odd rows) and converted
// as 65536 q: clang 14 turns wasm_i32x4_extend_low_i16x8 followed by a conversion into lane-by-lane
// scalar code. The accumulators are put back into row order once at the end. (Two or four panels
// at a time measured the same.)
void tile_wasm(const Model& m, std::size_t c, const float* sg, float* out) {
    const uint32_t K = m.component_count();
    const int16_t* panel = m.basis_panels() + c * K * kChunk;
    const float* mean = m.mean_planar() + c * kChunk;
    v128_t even[2], odd[2];  // rows 0 2 4 6 / 1 3 5 7 of each half panel
    for (int h = 0; h < 2; ++h) {
        const v128_t lo = wasm_v128_load(mean + 8 * h), hi = wasm_v128_load(mean + 8 * h + 4);
        even[h] = wasm_i32x4_shuffle(lo, hi, 0, 2, 4, 6);
        odd[h] = wasm_i32x4_shuffle(lo, hi, 1, 3, 5, 7);
    }
    const v128_t high = wasm_i32x4_splat(int32_t(0xFFFF0000u));
    for (uint32_t k = 0; k < K; ++k) {
        // The rows come as 65536 q (exact in a float), so the coefficient is scaled by 2^-16 (exact
        // too): each product is c q rounded once, as without the scaling.
        const v128_t ck = wasm_f32x4_splat(sg[k] * (1.f / 65536.f));
        const int16_t* q = panel + std::size_t(k) * kChunk;
        for (int h = 0; h < 2; ++h) {
            const v128_t pairs = wasm_v128_load(q + 8 * h);
            const v128_t e = wasm_f32x4_convert_i32x4(wasm_i32x4_shl(pairs, 16));
            const v128_t o = wasm_f32x4_convert_i32x4(wasm_v128_and(pairs, high));
            even[h] = wasm_f32x4_add(wasm_f32x4_mul(ck, e), even[h]);
            odd[h] = wasm_f32x4_add(wasm_f32x4_mul(ck, o), odd[h]);
        }
    }
    for (int h = 0; h < 2; ++h) {
        float* row = out + c * kChunk + 8 * h;
        wasm_v128_store(row, wasm_i32x4_shuffle(even[h], odd[h], 0, 4, 1, 5));
        wasm_v128_store(row + 4, wasm_i32x4_shuffle(even[h], odd[h], 2, 6, 3, 7));
    }
}

void shape_wasm(const Model& m, std::size_t count, const float* const* scaled, float* const* rest, std::size_t first, std::size_t end) {
    for (std::size_t g = 0; g < count; ++g)
        for (std::size_t c = first; c < end; ++c) tile_wasm(m, c, scaled[g], rest[g]);
}
#endif

[[maybe_unused]] void shape_scalar(const Model& m, std::size_t count, const float* const* scaled, float* const* rest, std::size_t first,
                                   std::size_t end) {
    const uint32_t K = m.component_count();
    for (std::size_t g = 0; g < count; ++g)
        for (std::size_t r = first * kChunk; r < end * kChunk; ++r) {
            const int16_t* panel = m.basis_panels() + (r / kChunk) * K * kChunk + r % kChunk;
            float acc = m.mean_planar()[r];
            for (uint32_t k = 0; k < K; ++k) acc = std::fma(scaled[g][k], float(panel[k * kChunk]), acc);
            rest[g][r] = acc;
        }
}

}  // namespace

void scale_coefficients(const Model& m, const float* coeffs, float* scaled) {
    for (uint32_t k = 0; k < m.component_count(); ++k) scaled[k] = coeffs[k] * m.basis_step()[k];
}

void shape(const Model& m, std::size_t count, const float* const* scaled, float* const* rest, float* const* joints) {
    shape_rows(m, count, scaled, rest, 0, m.padded_rows() / kChunk);
    shape_joints(m, count, scaled, joints);
}

void shape_rows(const Model& m, std::size_t count, const float* const* scaled, float* const* rest, std::size_t first_panel,
                std::size_t end_panel) {
    shape_rows(m, count, scaled, rest, first_panel, end_panel, active_isa());
}

void shape_rows(const Model& m, std::size_t count, const float* const* scaled, float* const* rest, std::size_t first_panel,
                std::size_t end_panel, Isa isa) {
    if (int(isa) > int(supported_isa())) isa = supported_isa();
#if defined(SSC_SHAPE_AVX512)
    if (isa == Isa::Avx512) return shape_avx512(m, count, scaled, rest, first_panel, end_panel);
#endif
#if defined(SSC_SHAPE_AVX2)
    if (isa != Isa::Baseline) return shape_avx2(m, count, scaled, rest, first_panel, end_panel);
#endif
#if defined(__wasm_simd128__)
    return shape_wasm(m, count, scaled, rest, first_panel, end_panel);
#endif
    shape_scalar(m, count, scaled, rest, first_panel, end_panel);
}

namespace {

// Baseline x86-64: std::fma is a call into libm there (exact, so the same bits as the AVX2 path's
// instructions).
[[gnu::always_inline]] inline void shape_joints_body(const Model& m, std::size_t count, const float* const* scaled,
                                                     float* const* joints) {
    const uint32_t J = m.joint_count(), K = m.component_count();
    for (std::size_t g = 0; g < count; ++g) {
        float* out = joints[g];
        for (uint32_t i = 0; i < 3 * J; ++i) {
            float acc = m.joint_mean()[i];
            for (uint32_t k = 0; k < K; ++k) acc = madd(scaled[g][k], m.joint_basis()[std::size_t(k) * 3 * J + i], acc);
            out[i] = acc;
        }
    }
}

#ifdef SSC_SHAPE_AVX2
SSC_TARGET_AVX2_BEGIN
// Sixteen outputs at a time, each accumulated over k in the same order as shape_joints_body (the
// same bits): the scalar loop is one dependent chain of K fused multiply-adds per output, which
// left the CPU waiting on each (4 us of a shape + pose on Zen 5; docs/speed.md).
void shape_joints_avx2(const Model& m, std::size_t count, const float* const* scaled, float* const* joints) {
    const uint32_t J = m.joint_count(), K = m.component_count(), n = 3 * J;
    const float* basis = m.joint_basis();
    for (std::size_t g = 0; g < count; ++g) {
        float* out = joints[g];
        const float* s = scaled[g];
        uint32_t i = 0;
        for (; i + 16 <= n; i += 16) {
            __m256 a0 = _mm256_loadu_ps(m.joint_mean() + i), a1 = _mm256_loadu_ps(m.joint_mean() + i + 8);
            for (uint32_t k = 0; k < K; ++k) {
                const __m256 c = _mm256_broadcast_ss(s + k);
                const float* row = basis + std::size_t(k) * n + i;
                a0 = _mm256_fmadd_ps(c, _mm256_loadu_ps(row), a0);
                a1 = _mm256_fmadd_ps(c, _mm256_loadu_ps(row + 8), a1);
            }
            _mm256_storeu_ps(out + i, a0);
            _mm256_storeu_ps(out + i + 8, a1);
        }
        for (; i < n; ++i) {
            float acc = m.joint_mean()[i];
            for (uint32_t k = 0; k < K; ++k) acc = madd(s[k], basis[std::size_t(k) * n + i], acc);
            out[i] = acc;
        }
    }
}
SSC_TARGET_END
#endif

}  // namespace

void shape_joints(const Model& m, std::size_t count, const float* const* scaled, float* const* joints) {
#ifdef SSC_SHAPE_AVX2
    if (active_isa() != Isa::Baseline) return shape_joints_avx2(m, count, scaled, joints);
#endif
    shape_joints_body(m, count, scaled, joints);
}

}  // namespace ssc::kernels
