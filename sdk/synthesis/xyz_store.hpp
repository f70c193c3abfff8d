// Eight vertices from planar registers to the caller's interleaved xyz (12 bytes a vertex): the
// output stage's step (kernels_output.cpp) and the skinning's when it writes the caller's buffer
// directly (kernels_skin_xyz.hpp). Pure data movement, so every path keeps the same bits.
#pragma once

#include "cpu.hpp"

#include <cstddef>
#include <cstdint>

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#include <immintrin.h>

namespace ssc::kernels {

SSC_TARGET_AVX2_BEGIN
// 8 vertices interleaved: the SSE steps of planar_to_xyz on both 128-bit lanes at once (lane 0
// vertices 0-3, lane 1 vertices 4-7), then the six 16-byte results put in output order by lane
// swaps.
[[gnu::always_inline]] inline void interleave8(__m256 x, __m256 y, __m256 z, __m256& o0, __m256& o1, __m256& o2) {
    const __m256 xy01 = _mm256_unpacklo_ps(x, y);
    const __m256 xy23 = _mm256_unpackhi_ps(x, y);
    const __m256 z0z1 = _mm256_shuffle_ps(z, z, _MM_SHUFFLE(1, 1, 0, 0));
    const __m256 a = _mm256_shuffle_ps(xy01, _mm256_shuffle_ps(z0z1, xy01, _MM_SHUFFLE(2, 2, 0, 0)), _MM_SHUFFLE(2, 0, 1, 0));
    const __m256 b = _mm256_shuffle_ps(_mm256_shuffle_ps(xy01, z, _MM_SHUFFLE(1, 1, 3, 3)), xy23, _MM_SHUFFLE(1, 0, 2, 0));
    const __m256 c = _mm256_shuffle_ps(_mm256_shuffle_ps(z, xy23, _MM_SHUFFLE(2, 2, 2, 2)), _mm256_shuffle_ps(xy23, z, _MM_SHUFFLE(3, 3, 3, 3)),
                                       _MM_SHUFFLE(2, 0, 2, 0));
    // a = [x0 y0 z0 x1 | x4 y4 z4 x5], b = [y1 z1 x2 y2 | y5 z5 x6 y6], c = [z2 x3 y3 z3 | z6 x7 y7 z7]
    o0 = _mm256_permute2f128_ps(a, b, 0x20);
    o1 = _mm256_permute2f128_ps(c, a, 0x30);
    o2 = _mm256_permute2f128_ps(b, c, 0x31);
}

// The 8 vertices vid[0..8) (a skin layout block's; a repeated last vertex rewrites the same
// values) into xyz: three whole stores where they are 8 consecutive vertices, else 12 bytes each,
// from registers: a shuffle puts each vertex's x, y, z in the low three floats of a 128-bit lane,
// then one 8-byte and one 4-byte store.
[[gnu::always_inline]] inline void store_xyz8(__m256 x, __m256 y, __m256 z, const uint32_t* vid, bool consecutive, float* xyz) {
    if (consecutive) {
        __m256 o0, o1, o2;
        interleave8(x, y, z, o0, o1, o2);
        float* o = xyz + 3 * std::size_t(vid[0]);
        _mm256_storeu_ps(o, o0);
        _mm256_storeu_ps(o + 8, o1);
        _mm256_storeu_ps(o + 16, o2);
        return;
    }
    const __m256 xy_lo = _mm256_unpacklo_ps(x, y);  // x0 y0 x1 y1 | x4 y4 x5 y5
    const __m256 xy_hi = _mm256_unpackhi_ps(x, y);  // x2 y2 x3 y3 | x6 y6 x7 y7
    const __m256 zz_lo = _mm256_unpacklo_ps(z, z);  // z0 z0 z1 z1 | z4 z4 z5 z5
    const __m256 zz_hi = _mm256_unpackhi_ps(z, z);  // z2 z2 z3 z3 | z6 z6 z7 z7
    const __m256 v[4] = {
        _mm256_shuffle_ps(xy_lo, zz_lo, _MM_SHUFFLE(0, 0, 1, 0)),  // x0 y0 z0 . | x4 y4 z4 .
        _mm256_shuffle_ps(xy_lo, zz_lo, _MM_SHUFFLE(2, 2, 3, 2)),  // vertices 1 | 5
        _mm256_shuffle_ps(xy_hi, zz_hi, _MM_SHUFFLE(0, 0, 1, 0)),  // 2 | 6
        _mm256_shuffle_ps(xy_hi, zz_hi, _MM_SHUFFLE(2, 2, 3, 2)),  // 3 | 7
    };
    auto put = [xyz](__m128 p, uint32_t vertex) {
        float* o = xyz + 3 * std::size_t(vertex);
        _mm_storel_pi(reinterpret_cast<__m64*>(o), p);
        _mm_store_ss(o + 2, _mm_movehl_ps(p, p));
    };
    for (int i = 0; i < 4; ++i) {
        put(_mm256_castps256_ps128(v[i]), vid[i]);
        put(_mm256_extractf128_ps(v[i], 1), vid[i + 4]);
    }
}
SSC_TARGET_END

// Where float f of an interleaved 8-vertex block comes from in (xy, z): xy holding the block's 8 x
// then its 8 y, z the block's z at lanes h .. h + 7 (the two-source permute's indices 16 + lane).
constexpr int32_t interleaved_source(int f, int h) { return f % 3 == 0 ? f / 3 : f % 3 == 1 ? 8 + f / 3 : 16 + h + f / 3; }
struct InterleaveIndices {
    alignas(64) int32_t low[16], high[16];  // floats 0-15 and 8-23 of the block
};
constexpr InterleaveIndices interleave_indices(int h) {
    InterleaveIndices t{};
    for (int l = 0; l < 16; ++l) t.low[l] = interleaved_source(l, h), t.high[l] = interleaved_source(8 + l, h);
    return t;
}
inline constexpr InterleaveIndices kInterleave[2] = {interleave_indices(0), interleave_indices(8)};

SSC_TARGET_AVX512_BEGIN
// The 8-vertex block in lanes 8 half .. 8 half + 7 of x, y, z written as store_xyz8 writes it,
// with AVX-512's masked stores: each vertex one store of its 3 floats of the interleaved block, at
// the address that puts them at its place (lanes outside a store's mask are neither written nor
// read, so that address may lie before xyz; it is formed as an integer).
[[gnu::always_inline]] inline void store_xyz8_masked(__m512 x, __m512 y, __m512 z, int half, const uint32_t* vid, bool consecutive, float* xyz) {
    const int h = 8 * half;
    const __m512i take_xy = _mm512_add_epi32(_mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23), _mm512_set1_epi32(h));
    const __m512 xy = _mm512_permutex2var_ps(x, take_xy, y);
    const InterleaveIndices& t = kInterleave[half];
    const __m512 low = _mm512_permutex2var_ps(xy, _mm512_load_si512(t.low), z);    // floats 0-15
    const __m512 high = _mm512_permutex2var_ps(xy, _mm512_load_si512(t.high), z);  // floats 8-23
    if (consecutive) {
        float* o = xyz + 3 * std::size_t(vid[0]);
        _mm512_storeu_ps(o, low);
        _mm512_mask_storeu_ps(o + 8, __mmask16(0xFF00), high);
        return;
    }
    const auto base = reinterpret_cast<std::uintptr_t>(xyz);
    for (int i = 0; i < 8; ++i) {
        const int lane = i < 5 ? 3 * i : 3 * i - 8;  // vertex i's floats 3i .. 3i + 2: in low up to vertex 4
        auto* o = reinterpret_cast<float*>(base + (3 * std::uintptr_t(vid[i]) - std::uintptr_t(lane)) * sizeof(float));
        _mm512_mask_storeu_ps(o, __mmask16(7u << lane), i < 5 ? low : high);
    }
}
SSC_TARGET_END

}  // namespace ssc::kernels
#endif
