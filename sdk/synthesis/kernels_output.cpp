// Output stage: planar coordinates (x block, y block, z block) to the caller's interleaved xyz, and
// between a skin layout's slot order and vertex order (skin_layout.hpp). Pure data movement: the
// values are copied, never recomputed, so every path gives the same bits.
//
// Why slot order: a body skins its full mesh with rest positions in slot order, so every 8-slot
// block is one load and one store (no gathers, no scatters, one forward stream per run); the
// gathers are then paid once per vertex here, on the way out, instead of inside the skinning.
#include "cpu.hpp"
#include "kernels.hpp"
#include "skin_layout.hpp"
#include "xyz_store.hpp"

#include <cstdint>

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#include <immintrin.h>
#define SSC_OUTPUT_AVX2 1
#endif

namespace ssc::kernels {
namespace {

#ifdef SSC_OUTPUT_AVX2
SSC_TARGET_AVX2_BEGIN
// Returns the vertices done (a multiple of 8).
uint32_t planar_to_xyz_avx2(const float* xs, const float* ys, const float* zs, uint32_t n, float* out, bool streaming) {
    uint32_t v = 0;
    for (; v + 8 <= n; v += 8) {
        __m256 o0, o1, o2;
        interleave8(_mm256_loadu_ps(xs + v), _mm256_loadu_ps(ys + v), _mm256_loadu_ps(zs + v), o0, o1, o2);
        float* o = out + 3 * std::size_t(v);
        if (streaming) {
            _mm256_stream_ps(o, o0);
            _mm256_stream_ps(o + 8, o1);
            _mm256_stream_ps(o + 16, o2);
        } else {
            _mm256_storeu_ps(o, o0);
            _mm256_storeu_ps(o + 8, o1);
            _mm256_storeu_ps(o + 16, o2);
        }
    }
    return v;
}

// Vertices [v, v + 8)'s slots: one load where they are 8 consecutive slots (as for most vertices
// of long runs), else a gather.
[[gnu::always_inline]] inline void load_slots8(const float* xs, const float* ys, const float* zs, const uint32_t* first_slot, uint32_t v, __m256& x,
                                               __m256& y, __m256& z) {
    const __m256i idx = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(first_slot + v));
    const __m256i consecutive = _mm256_add_epi32(_mm256_set1_epi32(int(first_slot[v])), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    if (_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(idx, consecutive))) == 0xFF) {
        const uint32_t s = first_slot[v];
        x = _mm256_loadu_ps(xs + s), y = _mm256_loadu_ps(ys + s), z = _mm256_loadu_ps(zs + s);
    } else {
        x = _mm256_i32gather_ps(xs, idx, 4), y = _mm256_i32gather_ps(ys, idx, 4), z = _mm256_i32gather_ps(zs, idx, 4);
    }
}

uint32_t slots_to_xyz_avx2(const float* xs, const float* ys, const float* zs, const uint32_t* first_slot, uint32_t first, uint32_t end, float* out) {
    uint32_t v = first;
    for (; v + 8 <= end; v += 8) {
        __m256 x, y, z, o0, o1, o2;
        load_slots8(xs, ys, zs, first_slot, v, x, y, z);
        interleave8(x, y, z, o0, o1, o2);
        float* o = out + 3 * std::size_t(v);
        _mm256_storeu_ps(o, o0);
        _mm256_storeu_ps(o + 8, o1);
        _mm256_storeu_ps(o + 16, o2);
    }
    return v;
}

uint32_t from_slot_order_avx2(const float* xs, const float* ys, const float* zs, const uint32_t* first_slot, uint32_t first, uint32_t end, float* ox,
                              float* oy, float* oz) {
    uint32_t v = first;
    for (; v + 8 <= end; v += 8) {
        __m256 x, y, z;
        load_slots8(xs, ys, zs, first_slot, v, x, y, z);
        _mm256_storeu_ps(ox + v, x);
        _mm256_storeu_ps(oy + v, y);
        _mm256_storeu_ps(oz + v, z);
    }
    return v;
}

uint32_t to_slot_order_avx2(const SkinLayout& layout, const float* xs, const float* ys, const float* zs, uint32_t first, uint32_t end, float* ox,
                            float* oy, float* oz) {
    const uint32_t* vid = layout.vertices.data();
    uint32_t s = first;
    for (; s + SkinLayout::kBlock <= end; s += SkinLayout::kBlock) {
        __m256 x, y, z;
        if (layout.contiguous[s / SkinLayout::kBlock]) {
            const uint32_t v = vid[s];
            x = _mm256_loadu_ps(xs + v), y = _mm256_loadu_ps(ys + v), z = _mm256_loadu_ps(zs + v);
        } else {
            const __m256i idx = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(vid + s));
            x = _mm256_i32gather_ps(xs, idx, 4), y = _mm256_i32gather_ps(ys, idx, 4), z = _mm256_i32gather_ps(zs, idx, 4);
        }
        _mm256_storeu_ps(ox + s, x);
        _mm256_storeu_ps(oy + s, y);
        _mm256_storeu_ps(oz + s, z);
    }
    return s;
}
SSC_TARGET_END

SSC_TARGET_AVX512_BEGIN
// As to_slot_order_avx2, but a block whose 8 vertices lie within 32 consecutive ones (sorted, so
// vid[7] - vid[0] < 32: 595 of the default model's 968 blocks that are not 8 consecutive
// vertices) is two loads and a permute per coordinate instead of a gather (the gathers bound this
// pass on Zen 5; docs/speed.md). Loads are masked to the coordinate's V values.
uint32_t to_slot_order_avx512(const SkinLayout& layout, const float* xs, const float* ys, const float* zs, uint32_t first, uint32_t end,
                              float* ox, float* oy, float* oz) {
    const uint32_t* vid = layout.vertices.data();
    const uint32_t V = layout.vertex_count;
    uint32_t s = first;
    for (; s + SkinLayout::kBlock <= end; s += SkinLayout::kBlock) {
        __m256 x, y, z;
        const uint32_t lo = vid[s];
        if (layout.contiguous[s / SkinLayout::kBlock]) {
            x = _mm256_loadu_ps(xs + lo), y = _mm256_loadu_ps(ys + lo), z = _mm256_loadu_ps(zs + lo);
        } else {
            if (vid[s + SkinLayout::kBlock - 1] - lo < 32) {
                // (16-lane registers throughout, the upper 8 lanes unused: GCC 12 warns falsely on
                // the 256/512-bit casts.)
                const __m512i rel = _mm512_sub_epi32(_mm512_maskz_loadu_epi32(0x00FF, vid + s), _mm512_set1_epi32(int(lo)));
                const uint32_t left = V - lo;
                const auto m0 = __mmask16(left >= 16 ? 0xFFFFu : (1u << left) - 1);
                const auto m1 = __mmask16(left >= 32 ? 0xFFFFu : left <= 16 ? 0u : (1u << (left - 16)) - 1);
                auto put = [&](const float* a, float* o) {
                    const __m512 v = _mm512_permutex2var_ps(_mm512_maskz_loadu_ps(m0, a + lo), rel, _mm512_maskz_loadu_ps(m1, a + lo + 16));
                    _mm512_mask_storeu_ps(o + s, 0x00FF, v);
                };
                put(xs, ox), put(ys, oy), put(zs, oz);
                continue;
            }
            const __m256i idx = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(vid + s));
            x = _mm256_i32gather_ps(xs, idx, 4), y = _mm256_i32gather_ps(ys, idx, 4), z = _mm256_i32gather_ps(zs, idx, 4);
        }
        _mm256_storeu_ps(ox + s, x);
        _mm256_storeu_ps(oy + s, y);
        _mm256_storeu_ps(oz + s, z);
    }
    return s;
}
SSC_TARGET_END
#endif

}  // namespace

void planar_to_xyz(const float* planar, uint32_t n, float* out, std::size_t stride, bool streaming) {
    const float* xs = planar;
    const float* ys = planar + n;
    const float* zs = planar + 2 * std::size_t(n);
    uint32_t v = 0;
#ifdef SSC_OUTPUT_AVX2
    // (Streaming stores of 32 bytes need 32-byte alignment: otherwise the SSE path's 16.)
    if (stride == 12 && active_isa() != Isa::Baseline && (!streaming || reinterpret_cast<std::uintptr_t>(out) % 32 == 0))
        v = planar_to_xyz_avx2(xs, ys, zs, n, out, streaming);
#endif
#if defined(__SSE2__)
    // SSE2 is part of x86-64 itself. Streaming (non-temporal) stores skip reading the destination
    // into cache first: they halve the memory traffic of large batch outputs that the caller will
    // not read back soon.
    streaming = streaming && reinterpret_cast<std::uintptr_t>(out) % 16 == 0;
    if (stride == 12) {  // packed: interleave 4 vertices per step with SSE shuffles
        for (; v + 4 <= n; v += 4) {
            const __m128 x = _mm_loadu_ps(xs + v), y = _mm_loadu_ps(ys + v), z = _mm_loadu_ps(zs + v);
            const __m128 xy01 = _mm_unpacklo_ps(x, y);                            // x0 y0 x1 y1
            const __m128 xy23 = _mm_unpackhi_ps(x, y);                            // x2 y2 x3 y3
            const __m128 z0z1 = _mm_shuffle_ps(z, z, _MM_SHUFFLE(1, 1, 0, 0));     // z0 z0 z1 z1
            const __m128 out0 = _mm_shuffle_ps(xy01, _mm_shuffle_ps(z0z1, xy01, _MM_SHUFFLE(2, 2, 0, 0)),
                                               _MM_SHUFFLE(2, 0, 1, 0));           // x0 y0 z0 x1
            const __m128 out1 = _mm_shuffle_ps(_mm_shuffle_ps(xy01, z, _MM_SHUFFLE(1, 1, 3, 3)), xy23,
                                               _MM_SHUFFLE(1, 0, 2, 0));           // y1 z1 x2 y2
            const __m128 out2 = _mm_shuffle_ps(_mm_shuffle_ps(z, xy23, _MM_SHUFFLE(2, 2, 2, 2)),
                                               _mm_shuffle_ps(xy23, z, _MM_SHUFFLE(3, 3, 3, 3)),
                                               _MM_SHUFFLE(2, 0, 2, 0));           // z2 x3 y3 z3
            float* o = out + 3 * std::size_t(v);
            if (streaming) {
                _mm_stream_ps(o, out0);
                _mm_stream_ps(o + 4, out1);
                _mm_stream_ps(o + 8, out2);
            } else {
                _mm_storeu_ps(o, out0);
                _mm_storeu_ps(o + 4, out1);
                _mm_storeu_ps(o + 8, out2);
            }
        }
    }
    if (streaming) _mm_sfence();
#else
    (void)streaming;
#endif
    auto* base = reinterpret_cast<unsigned char*>(out);
    for (; v < n; ++v) {
        float* p = reinterpret_cast<float*>(base + v * stride);
        p[0] = xs[v];
        p[1] = ys[v];
        p[2] = zs[v];
    }
}

void to_slot_order(const SkinLayout& layout, const float* planar, float* slots, uint32_t first, uint32_t end) {
    const uint32_t V = layout.vertex_count, S = layout.slot_count();
    const float *xs = planar, *ys = planar + V, *zs = planar + 2 * std::size_t(V);
    float *ox = slots, *oy = slots + S, *oz = slots + 2 * std::size_t(S);
    uint32_t s = first;
#ifdef SSC_OUTPUT_AVX2
    if (active_isa() == Isa::Avx512 && first % SkinLayout::kBlock == 0) s = to_slot_order_avx512(layout, xs, ys, zs, first, end, ox, oy, oz);
    else if (active_isa() != Isa::Baseline && first % SkinLayout::kBlock == 0) s = to_slot_order_avx2(layout, xs, ys, zs, first, end, ox, oy, oz);
#endif
    for (; s < end; ++s) {
        const uint32_t v = layout.vertices[s];
        ox[s] = xs[v], oy[s] = ys[v], oz[s] = zs[v];
    }
}

void from_slot_order(const SkinLayout& layout, const float* slots, float* planar, uint32_t first, uint32_t end) {
    const uint32_t V = layout.vertex_count, S = layout.slot_count();
    const float *xs = slots, *ys = slots + S, *zs = slots + 2 * std::size_t(S);
    float *ox = planar, *oy = planar + V, *oz = planar + 2 * std::size_t(V);
    const uint32_t* slot = layout.first_slot.data();
    uint32_t v = first;
#ifdef SSC_OUTPUT_AVX2
    if (active_isa() != Isa::Baseline) v = from_slot_order_avx2(xs, ys, zs, slot, first, end, ox, oy, oz);
#endif
    for (; v < end; ++v) ox[v] = xs[slot[v]], oy[v] = ys[slot[v]], oz[v] = zs[slot[v]];
}

void slots_to_xyz(const SkinLayout& layout, const float* slots, float* out, std::size_t stride, uint32_t first, uint32_t end) {
    const uint32_t S = layout.slot_count();
    const float *xs = slots, *ys = slots + S, *zs = slots + 2 * std::size_t(S);
    const uint32_t* slot = layout.first_slot.data();
    uint32_t v = first;
#ifdef SSC_OUTPUT_AVX2
    if (stride == 12 && active_isa() != Isa::Baseline) v = slots_to_xyz_avx2(xs, ys, zs, slot, first, end, out);
#endif
    auto* base = reinterpret_cast<unsigned char*>(out);
    for (; v < end; ++v) {
        float* p = reinterpret_cast<float*>(base + v * stride);
        p[0] = xs[slot[v]], p[1] = ys[slot[v]], p[2] = zs[slot[v]];
    }
}

}  // namespace ssc::kernels
