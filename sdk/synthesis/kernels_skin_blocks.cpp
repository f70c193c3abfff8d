// Skinning in vertex order by blocks of 16 vertices and the union of their joints (skin_blocks.hpp).
//
// Per lane the arithmetic of SkinLayout's skinning (kernels_pose.cpp): the 12 matrix elements
// blended as w_0 M_0 + w_1 M_1 + ... in joint order (the first a product, the rest fused
// multiply-adds), then p = (m0 x + m8 z) + (m4 y + m12) per row. The blend starts from -0, and
// fma(w, M, -0) rounds w M exactly as the product does (x + -0 = x for every x, signed zeros
// included); a joint that does not move a lane leaves that lane's sum untouched (a masked
// multiply-add), so every lane gets the same bits as before. AVX-512 only: AVX2 has no masked
// multiply-add, and a blend after each made its blocks slower than the skin layout's runs with their
// gathers (docs/speed.md); other instruction sets run the blocks one vertex at a time.
#include "cpu.hpp"
#include "kernels.hpp"
#include "madd.hpp"
#include "skin_blocks.hpp"

#include <algorithm>
#include <cstddef>

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#include <immintrin.h>
#define SSC_BLOCKS_X86 1
#endif

namespace ssc::kernels {
namespace {

constexpr uint32_t L = SkinBlocks::kLanes;
// The rows' elements in a column-major 4x4: x, y and z coefficients and the translation.
constexpr int kRowX[4] = {0, 4, 8, 12}, kRowY[4] = {1, 5, 9, 13}, kRowZ[4] = {2, 6, 10, 14};
constexpr int kElements[12] = {0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14};

// Block b one vertex at a time (the last, partial block, and the baseline path).
void skin_block_scalar(const SkinBlocks& s, uint32_t b, const float* rest, const float* mats, float* out, float* xyz) {
    const uint32_t V = s.vertex_count;
    for (uint32_t l = 0; l < L && L * b + l < V; ++l) {
        const uint32_t v = L * b + l;
        float m[15];
        for (int e : kElements) m[e] = -0.f;
        for (uint32_t i = s.first[b]; i < s.first[b + 1]; ++i) {
            if (!(s.lanes[i] >> l & 1u)) continue;
            const float* M = mats + s.offsets[i];
            const float w = s.weights[std::size_t(i) * L + l];
            for (int e : kElements) m[e] = madd(w, M[e], m[e]);
        }
        const float x = rest[v], y = rest[V + v], z = rest[2 * std::size_t(V) + v];
        auto row = [&](const int* e) { return madd(m[e[2]], z, m[e[0]] * x) + madd(m[e[1]], y, m[e[3]]); };
        const float px = row(kRowX), py = row(kRowY), pz = row(kRowZ);
        if (out) out[v] = px, out[V + v] = py, out[2 * std::size_t(V) + v] = pz;
        if (xyz) xyz[3 * std::size_t(v)] = px, xyz[3 * std::size_t(v) + 1] = py, xyz[3 * std::size_t(v) + 2] = pz;
    }
}

#ifdef SSC_BLOCKS_X86

// Where float i of the k-th 16 floats of 16 interleaved vertices comes from: first from (x, y)
// (x lanes 0-15, y 16-31), then from (that, z) (itself 0-15, z 16-31).
struct Interleave16 {
    alignas(64) int32_t xy[3][16], z[3][16];
};
constexpr Interleave16 interleave16() {
    Interleave16 t{};
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 16; ++i) {
            const int f = 16 * k + i, v = f / 3, c = f % 3;
            t.xy[k][i] = c == 0 ? v : c == 1 ? 16 + v : 0;
            t.z[k][i] = c == 2 ? 16 + v : i;
        }
    return t;
}
inline constexpr Interleave16 kInterleave16 = interleave16();

SSC_TARGET_AVX512_BEGIN
// Blocks in vertex order (a hardware prefetcher's stream: after the shape stage has evicted the rest
// positions, an order of blocks grouped by joint count took 2 us more a body). Planar and Xyz: which
// outputs are written.
template <bool Planar, bool Xyz>
void skin_blocks_avx512(const SkinBlocks& s, const float* rest, const float* mats, float* out, float* xyz, uint32_t first, uint32_t end) {
    const uint32_t V = s.vertex_count;
    const float *xs = rest, *ys = rest + V, *zs = rest + 2 * std::size_t(V);
    float *ox = nullptr, *oy = nullptr, *oz = nullptr;
    if constexpr (Planar) ox = out, oy = out + V, oz = out + 2 * std::size_t(V);
    const float* weights = s.weights.data();
    for (uint32_t b = first; b < end; ++b) {
        if (L * (b + 1) > V) {
            skin_block_scalar(s, b, rest, mats, Planar ? out : nullptr, Xyz ? xyz : nullptr);
            continue;
        }
        const uint32_t v0 = L * b;
        __m512 m[15];
        if (s.unit[b]) {
            const float* M = mats + s.offsets[s.first[b]];
            _Pragma("GCC unroll 12") for (int e : kElements) m[e] = _mm512_set1_ps(M[e]);
        } else {
            _Pragma("GCC unroll 12") for (int e : kElements) m[e] = _mm512_set1_ps(-0.f);
            for (uint32_t i = s.first[b]; i < s.first[b + 1]; ++i) {
                const float* M = mats + s.offsets[i];
                const __m512 w = _mm512_loadu_ps(weights + std::size_t(i) * L);
                const __mmask16 moves = s.lanes[i];
                _Pragma("GCC unroll 12") for (int e : kElements) m[e] = _mm512_mask3_fmadd_ps(w, _mm512_set1_ps(M[e]), m[e], moves);
            }
        }
        const __m512 x = _mm512_loadu_ps(xs + v0), y = _mm512_loadu_ps(ys + v0), z = _mm512_loadu_ps(zs + v0);
        auto row = [&](const int* e) {
            return _mm512_add_ps(_mm512_fmadd_ps(m[e[2]], z, _mm512_mul_ps(m[e[0]], x)), _mm512_fmadd_ps(m[e[1]], y, m[e[3]]));
        };
        const __m512 px = row(kRowX), py = row(kRowY), pz = row(kRowZ);
        if constexpr (Planar) {
            _mm512_storeu_ps(ox + v0, px);
            _mm512_storeu_ps(oy + v0, py);
            _mm512_storeu_ps(oz + v0, pz);
        }
        if constexpr (Xyz) {
            float* o = xyz + 3 * std::size_t(v0);
            _Pragma("GCC unroll 3") for (int k = 0; k < 3; ++k) {
                const __m512 t = _mm512_permutex2var_ps(px, _mm512_load_si512(kInterleave16.xy[k]), py);
                _mm512_storeu_ps(o + 16 * k, _mm512_permutex2var_ps(t, _mm512_load_si512(kInterleave16.z[k]), pz));
            }
        }
    }
}
SSC_TARGET_END
#endif

}  // namespace

void skin_blocks(const SkinBlocks& s, const float* rest, const SkinMatrix* skinning, float* out, float* xyz, uint32_t first, uint32_t end, Isa isa) {
    if (int(isa) > int(supported_isa())) isa = supported_isa();
    const float* mats = skinning[0].m;
#ifdef SSC_BLOCKS_X86
    if (isa == Isa::Avx512) {
        if (!out) return skin_blocks_avx512<false, true>(s, rest, mats, nullptr, xyz, first, end);
        if (!xyz) return skin_blocks_avx512<true, false>(s, rest, mats, out, nullptr, first, end);
        return skin_blocks_avx512<true, true>(s, rest, mats, out, xyz, first, end);
    }
#endif
    (void)isa;
    for (uint32_t b = first; b < end; ++b) skin_block_scalar(s, b, rest, mats, out, xyz);
}

}  // namespace ssc::kernels
