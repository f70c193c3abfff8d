// Skeleton and skinning stages.
//
// Joint j has rest world position p_j (from the shape) and rest local orientation R_j. Its rest
// world rotation is W_j = W_parent * R_j, and its offset in the parent's frame is
// o_j = W_parent^T (p_j - p_parent). Posed: G_j = G_parent * [R_j * P_j | o_j], with P_j the pose
// rotation; the root is [R_root * P_root | p_root + translation]. The bind transform is
// [W_j | p_j], and skinning uses G_j * bind_j^-1, which is the identity in the zero pose.
#include "cpu.hpp"
#include "kernels.hpp"
#include "kernels_skin_xyz.hpp"
#include "madd.hpp"
#include "model.hpp"
#include "xyz_store.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#include <immintrin.h>
#define SSC_SKIN_AVX2 1
#endif
#if defined(__wasm_simd128__)
#include <wasm_simd128.h>
#endif

namespace ssc::kernels {
namespace {

using Eigen::Matrix3f;
using Eigen::Vector3f;

void store16(const Matrix3f& r, const Vector3f& t, float* out) {
    for (int c = 0; c < 3; ++c) {
        for (int row = 0; row < 3; ++row) out[c * 4 + row] = r(row, c);
        out[c * 4 + 3] = 0.f;
    }
    out[12] = t.x();
    out[13] = t.y();
    out[14] = t.z();
    out[15] = 1.f;
}

}  // namespace

// Per joint in rest_frames (kSkeletonRest floats): R (the normalized rest local orientation), W
// (the rest world rotation), o (the offset from the parent in its frame), bt (the bind inverse's
// translation -W^T p) and p (the rest world position): everything that depends on the shape
// only, so a body computes it once per shape and each posing does the rest.
namespace {
using Map3 = Eigen::Map<Matrix3f>;
using MapV = Eigen::Map<Vector3f>;
// A joint's rest frame in rest_frames: writable (Float = float) or read-only (const float).
template <class Float>
struct RestFrameOf {
    template <class M>
    using MapOf = Eigen::Map<std::conditional_t<std::is_const_v<Float>, const M, M>>;
    Float* f;
    MapOf<Matrix3f> R() const { return MapOf<Matrix3f>(f); }
    MapOf<Matrix3f> W() const { return MapOf<Matrix3f>(f + 9); }
    MapOf<Vector3f> o() const { return MapOf<Vector3f>(f + 18); }
    MapOf<Vector3f> bt() const { return MapOf<Vector3f>(f + 21); }
    MapOf<Vector3f> p() const { return MapOf<Vector3f>(f + 24); }
};
using RestFrame = RestFrameOf<float>;
}  // namespace

void skeleton_rest(const Model& m, const float* joints_rest, float* rest_frames, float* inverse_bind16) {
    const uint32_t J = m.joint_count();
    const auto& sk = m.data().skeleton;
    auto frame = [&](uint32_t j) { return RestFrame{rest_frames + kSkeletonRest * std::size_t(j)}; };
    for (uint32_t j = 0; j < J; ++j) {
        const RestFrame f = frame(j);
        const float* rq = &sk.rest_orientations[4 * j];
        f.R() = Eigen::Quaternionf(rq[3], rq[0], rq[1], rq[2]).normalized().toRotationMatrix();
        const Vector3f p(joints_rest + 3 * j);
        f.p() = p;
        const int32_t parent = sk.parents[j];
        if (parent < 0) {
            f.W() = f.R();
            f.o().setZero();
        } else {
            const RestFrame up = frame(static_cast<uint32_t>(parent));
            f.o() = up.W().transpose() * (p - Vector3f(joints_rest + 3 * std::size_t(parent)));
            f.W() = up.W() * f.R();
        }
        // Bind inverse: [W^T | -W^T p].
        const Matrix3f Wt = f.W().transpose();
        f.bt() = -(Wt * p);
        if (inverse_bind16) store16(Wt, f.bt(), inverse_bind16 + 16 * j);
    }
}

void skeleton_pose(const Model& m, const float* rest_frames, const float* quats, const float* translation, float* scratch, float* world16,
                   SkinMatrix* skinning) {
    const uint32_t J = m.joint_count();
    const auto& sk = m.data().skeleton;
    // Per joint: posed world rotation G and translation Gt (9 + 3 floats).
    auto G = [&](uint32_t j) { return Map3(scratch + 12 * std::size_t(j)); };
    auto Gt = [&](uint32_t j) { return MapV(scratch + 12 * std::size_t(j) + 9); };
    for (uint32_t j = 0; j < J; ++j) {
        const RestFrameOf<const float> f{rest_frames + kSkeletonRest * std::size_t(j)};
        const float* pq = quats + 4 * j;
        const Matrix3f P = Eigen::Quaternionf(pq[3], pq[0], pq[1], pq[2]).toRotationMatrix();
        const Matrix3f R = f.R();
        const int32_t parent = sk.parents[j];
        if (parent < 0) {
            G(j) = R * P;
            Gt(j) = f.p() + Vector3f(translation);
        } else {
            const auto up = static_cast<uint32_t>(parent);
            const Vector3f offset = f.o();
            G(j) = G(up) * (R * P);
            Gt(j) = G(up) * offset + Gt(up);
        }
        const Matrix3f Wt = f.W().transpose();
        const Vector3f bt = f.bt();
        if (world16) store16(G(j), Gt(j), world16 + 16 * j);
        if (skinning) store16(G(j) * Wt, G(j) * bt + Gt(j), skinning[j].m);
    }
}

void skeleton(const Model& m, const float* joints_rest, const float* quats, const float* translation, float* scratch, float* world16,
              float* inverse_bind16, SkinMatrix* skinning) {
    float* rest_frames = scratch;
    skeleton_rest(m, joints_rest, rest_frames, inverse_bind16);
    skeleton_pose(m, rest_frames, quats, translation, scratch + kSkeletonRest * std::size_t(m.joint_count()), world16, skinning);
}

namespace {

// The 12 elements of a column-major 4x4 affine matrix that skinning uses: rows 0..2 of each column.
constexpr int kRowX[4] = {0, 4, 8, 12}, kRowY[4] = {1, 5, 9, 13}, kRowZ[4] = {2, 6, 10, 14};

// Where the SIMD paths read and write positions, as template arguments: vertex order, slot order,
// or slot order with the caller's xyz written as well (kernels_skin_xyz.hpp).
enum class Order { Vertex, Slots, SlotsAndXyz };

// A lambda that must be inlined into its caller: the per-block kernels are lambdas, and with a run
// function instantiated per order and influence count GCC's inliner stops inlining them otherwise
// (a call per block, a third slower).
#define SSC_INLINE_LAMBDA __attribute__((always_inline))

// One run: N joints shared by every vertex, weights per vertex. Blends the 12 matrix elements
// w_0 M_0 + w_1 M_1 + ... (FMAs in influence order) and transforms:
// p = (m0 x + m8 z) + (m4 y + m12) per row, the same order in the SIMD and the scalar path.
// What a run reads and writes: planar rest and output coordinates, and per influence its matrix
// and its weights.
//
// The planar positions are in vertex order (blocks of the mesh's vertex_count: slot s is vertex
// vertices[s], a block loaded whole where its vertices are consecutive, else gathered and
// scattered) or, with `slots`, in the layout's own slot order (blocks of slot_count(): slot s at
// s, every block whole; see skin_slots_in_slot_order).
template <int N>
struct RunArrays {
    const float* xs;
    const float* ys;
    const float* zs;
    float* ox;
    float* oy;
    float* oz;
    const float* M[N];
    const float* W[N];
};

template <int N>
RunArrays<N> arrays(const SkinLayout& m, const SkinLayout::Run& run, const float* mats, const float* rest, float* out, bool slots) {
    const uint32_t V = slots ? m.slot_count() : m.vertex_count;
    RunArrays<N> a{rest, rest + V, rest + 2 * std::size_t(V), out, out + V, out + 2 * std::size_t(V), {}, {}};
    for (int i = 0; i < N; ++i) {
        a.M[i] = mats + run.offsets[i];
        a.W[i] = m.weights[i].data();
    }
    return a;
}

template <int N>
void skin_run_scalar(const SkinLayout& m, const SkinLayout::Run& run, const float* mats, const float* rest, float* out, bool slots, float* xyz) {
    const RunArrays<N> a = arrays<N>(m, run, mats, rest, out, slots);
    const float* const* M = a.M;
    const float* const* W = a.W;
    const uint32_t* vid = m.vertices.data();
    for (uint32_t s = run.begin; s < run.end; ++s) {
        const uint32_t v = slots ? s : vid[s];
        auto blend = [&](int e) SSC_INLINE_LAMBDA {
            float acc = W[0][s] * M[0][e];
            for (int i = 1; i < N; ++i) acc = madd(W[i][s], M[i][e], acc);
            return acc;
        };
        auto row = [&](const int* e) SSC_INLINE_LAMBDA {
            return madd(blend(e[2]), a.zs[v], blend(e[0]) * a.xs[v]) + madd(blend(e[1]), a.ys[v], blend(e[3]));
        };
        a.ox[v] = row(kRowX);
        a.oy[v] = row(kRowY);
        a.oz[v] = row(kRowZ);
        if (xyz) {
            float* p = xyz + 3 * std::size_t(vid[s]);
            p[0] = a.ox[v], p[1] = a.oy[v], p[2] = a.oz[v];
        }
    }
}

#ifdef SSC_SKIN_AVX2
SSC_TARGET_AVX2_BEGIN
// Whether every slot of a one-joint run has weight 1 (a normalized skin's vertices on a single joint:
// half of the default model's). Then w M = M exactly, and the run's matrix elements are broadcast
// once for the whole run instead of once per block.
bool unit_weights_avx2(const SkinLayout& m, const SkinLayout::Run& run) {
    const __m256 one = _mm256_set1_ps(1.f);
    const float* w = m.weights[0].data();
    for (uint32_t b = run.begin; b < run.end; b += SkinLayout::kBlock)
        if (_mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(w + b), one, _CMP_NEQ_UQ)) != 0) return false;
    return true;
}

// The blocks of a run: each block's 8 rest positions loaded (consecutive vertices) or gathered,
// skin(b, x, y, z, px, py, pz) computing the posed ones, stored or scattered back (and with xyz,
// written there too).
template <Order O, class Skin>
[[gnu::always_inline]] inline void each_block_avx2(const SkinLayout& m, const SkinLayout::Run& run, const float* rest, float* out,
                                                  float* xyz, Skin&& skin) {
    constexpr bool slots = O != Order::Vertex;
    const uint32_t V = slots ? m.slot_count() : m.vertex_count;
    const float *xs = rest, *ys = rest + V, *zs = rest + 2 * std::size_t(V);
    float *ox = out, *oy = out + V, *oz = out + 2 * std::size_t(V);
    const uint32_t* vid = m.vertices.data();
    for (uint32_t b = run.begin; b < run.end; b += SkinLayout::kBlock) {
        const uint32_t v0 = slots ? b : vid[b];
        __m256 px, py, pz;
        if (slots || m.contiguous[b / SkinLayout::kBlock]) {
            skin(b, _mm256_loadu_ps(xs + v0), _mm256_loadu_ps(ys + v0), _mm256_loadu_ps(zs + v0), px, py, pz);
            _mm256_storeu_ps(ox + v0, px);
            _mm256_storeu_ps(oy + v0, py);
            _mm256_storeu_ps(oz + v0, pz);
        } else {
            const __m256i idx = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(vid + b));
            skin(b, _mm256_i32gather_ps(xs, idx, 4), _mm256_i32gather_ps(ys, idx, 4), _mm256_i32gather_ps(zs, idx, 4), px, py, pz);
            alignas(32) float tx[8], ty[8], tz[8];
            alignas(32) uint32_t ti[8];
            _mm256_store_ps(tx, px);
            _mm256_store_ps(ty, py);
            _mm256_store_ps(tz, pz);
            _mm256_store_si256(reinterpret_cast<__m256i*>(ti), idx);
            for (int l = 0; l < 8; ++l) {
                ox[ti[l]] = tx[l];
                oy[ti[l]] = ty[l];
                oz[ti[l]] = tz[l];
            }
        }
        if constexpr (O == Order::SlotsAndXyz) store_xyz8(px, py, pz, vid + b, m.contiguous[b / SkinLayout::kBlock], xyz);
    }
}

// A one-joint run of weight 1: the arithmetic of skin_run_avx2<1> below with blend(e) = M[e], so the
// same bits, with the twelve broadcasts made once.
template <Order O>
void skin_run_unit_avx2(const SkinLayout& m, const SkinLayout::Run& run, const float* mats, const float* rest, float* out, float* xyz) {
    const float* M = mats + run.offsets[0];
    __m256 k[15];  // elements 0..14 of the column-major 4x4 (row 3 unused)
    for (int e = 0; e < 15; ++e) k[e] = _mm256_broadcast_ss(M + e);
    each_block_avx2<O>(m, run, rest, out, xyz, [&](uint32_t, __m256 x, __m256 y, __m256 z, __m256& px, __m256& py, __m256& pz) SSC_INLINE_LAMBDA {
        auto row = [&](const int* e) SSC_INLINE_LAMBDA {
            return _mm256_add_ps(_mm256_fmadd_ps(k[e[2]], z, _mm256_mul_ps(k[e[0]], x)), _mm256_fmadd_ps(k[e[1]], y, k[e[3]]));
        };
        px = row(kRowX), py = row(kRowY), pz = row(kRowZ);
    });
}

template <int N, Order O>
void skin_run_avx2(const SkinLayout& m, const SkinLayout::Run& run, const float* mats, const float* rest, float* out, float* xyz) {
    if constexpr (N == 1)
        if (unit_weights_avx2(m, run)) return skin_run_unit_avx2<O>(m, run, mats, rest, out, xyz);
    const RunArrays<N> a = arrays<N>(m, run, mats, rest, out, O != Order::Vertex);
    const float* const* M = a.M;
    const float* const* W = a.W;
    each_block_avx2<O>(m, run, rest, out, xyz, [&](uint32_t b, __m256 x, __m256 y, __m256 z, __m256& px, __m256& py, __m256& pz) SSC_INLINE_LAMBDA {
        __m256 w[N];
        for (int i = 0; i < N; ++i) w[i] = _mm256_loadu_ps(W[i] + b);
        auto blend = [&](int e) SSC_INLINE_LAMBDA {
            __m256 acc = _mm256_mul_ps(w[0], _mm256_broadcast_ss(M[0] + e));
            for (int i = 1; i < N; ++i) acc = _mm256_fmadd_ps(w[i], _mm256_broadcast_ss(M[i] + e), acc);
            return acc;
        };
        auto row = [&](const int* e) SSC_INLINE_LAMBDA {
            const __m256 p = _mm256_fmadd_ps(blend(e[2]), z, _mm256_mul_ps(blend(e[0]), x));
            const __m256 c = _mm256_fmadd_ps(blend(e[1]), y, blend(e[3]));
            return _mm256_add_ps(p, c);
        };
        px = row(kRowX), py = row(kRowY), pz = row(kRowZ);
    });
}
SSC_TARGET_END

// AVX-512: two blocks of a run per step (16 lanes), a run's odd last block in the low 8 lanes under
// a mask. Lane for lane the same operations as skin_run_avx2, so the same bits.
SSC_TARGET_AVX512_BEGIN

bool unit_weights_avx512(const SkinLayout& m, const SkinLayout::Run& run) {
    const __m512 one = _mm512_set1_ps(1.f);
    const float* w = m.weights[0].data();
    for (uint32_t b = run.begin; b < run.end; b += SkinLayout::kBlock)
        if (_mm512_mask_cmp_ps_mask(0x00FF, _mm512_maskz_loadu_ps(0x00FF, w + b), one, _CMP_NEQ_UQ) != 0) return false;
    return true;
}

// The 16-slot steps of a run: rest positions loaded (16 consecutive vertices) or
// gathered, skin(b, mask, x, y, z, px, py, pz) computing the posed ones, stored or scattered back
// (and with xyz, written there too, a block of 8 at a time).
template <Order O, class Skin>
[[gnu::always_inline]] inline void each_block_avx512(const SkinLayout& m, const SkinLayout::Run& run, const float* rest, float* out,
                                                    float* xyz, Skin&& skin) {
    constexpr bool slots = O != Order::Vertex;
    const uint32_t V = slots ? m.slot_count() : m.vertex_count;
    const float *xs = rest, *ys = rest + V, *zs = rest + 2 * std::size_t(V);
    float *ox = out, *oy = out + V, *oz = out + 2 * std::size_t(V);
    const uint32_t* vid = m.vertices.data();
    const uint8_t* contiguous = m.contiguous.data();
    for (uint32_t b = run.begin; b < run.end; b += 2 * SkinLayout::kBlock) {
        const bool two = b + 2 * SkinLayout::kBlock <= run.end;
        const __mmask16 k = two ? __mmask16(0xFFFF) : __mmask16(0x00FF);
        const uint32_t v0 = slots ? b : vid[b], blk = b / SkinLayout::kBlock;
        __m512 px, py, pz;
        if (slots || (contiguous[blk] && (!two || (contiguous[blk + 1] && vid[b + SkinLayout::kBlock] == v0 + SkinLayout::kBlock)))) {
            if (two) {
            skin(b, k, _mm512_loadu_ps(xs + v0), _mm512_loadu_ps(ys + v0), _mm512_loadu_ps(zs + v0), px, py, pz);
            _mm512_storeu_ps(ox + v0, px);
            _mm512_storeu_ps(oy + v0, py);
            _mm512_storeu_ps(oz + v0, pz);
            } else {
            skin(b, k, _mm512_maskz_loadu_ps(k, xs + v0), _mm512_maskz_loadu_ps(k, ys + v0), _mm512_maskz_loadu_ps(k, zs + v0), px, py, pz);
            _mm512_mask_storeu_ps(ox + v0, k, px);
            _mm512_mask_storeu_ps(oy + v0, k, py);
            _mm512_mask_storeu_ps(oz + v0, k, pz);
            }
        } else {
            const __m512i idx = _mm512_maskz_loadu_epi32(k, vid + b);
            const __m512 zero = _mm512_setzero_ps();
            skin(b, k, _mm512_mask_i32gather_ps(zero, k, idx, xs, 4), _mm512_mask_i32gather_ps(zero, k, idx, ys, 4),
                 _mm512_mask_i32gather_ps(zero, k, idx, zs, 4), px, py, pz);
            // Scattered by scalar stores, as the AVX2 path does: vscatterdps is slower on AMD
            // (this stage 26.1 against 23.5 us on Zen 5; docs/speed.md).
            alignas(64) float tx[16], ty[16], tz[16];
            _mm512_store_ps(tx, px);
            _mm512_store_ps(ty, py);
            _mm512_store_ps(tz, pz);
            const int lanes = two ? 16 : 8;
            for (int l = 0; l < lanes; ++l) {
                const uint32_t v = vid[b + l];
                ox[v] = tx[l], oy[v] = ty[l], oz[v] = tz[l];
            }
        }
        if constexpr (O == Order::SlotsAndXyz) {
            store_xyz8_masked(px, py, pz, 0, vid + b, contiguous[blk], xyz);
            if (two) store_xyz8_masked(px, py, pz, 1, vid + b + SkinLayout::kBlock, contiguous[blk + 1], xyz);
        }
    }
}

template <Order O>
void skin_run_unit_avx512(const SkinLayout& m, const SkinLayout::Run& run, const float* mats, const float* rest, float* out, float* xyz) {
    const float* M = mats + run.offsets[0];
    __m512 k[15];
    for (int e = 0; e < 15; ++e) k[e] = _mm512_set1_ps(M[e]);
    each_block_avx512<O>(m, run, rest, out, xyz, [&](uint32_t, __mmask16, __m512 x, __m512 y, __m512 z, __m512& px, __m512& py, __m512& pz) SSC_INLINE_LAMBDA {
        auto row = [&](const int* e) SSC_INLINE_LAMBDA {
            return _mm512_add_ps(_mm512_fmadd_ps(k[e[2]], z, _mm512_mul_ps(k[e[0]], x)), _mm512_fmadd_ps(k[e[1]], y, k[e[3]]));
        };
        px = row(kRowX), py = row(kRowY), pz = row(kRowZ);
    });
}

template <int N, Order O>
void skin_run_avx512(const SkinLayout& m, const SkinLayout::Run& run, const float* mats, const float* rest, float* out, float* xyz) {
    if constexpr (N == 1)
        if (unit_weights_avx512(m, run)) return skin_run_unit_avx512<O>(m, run, mats, rest, out, xyz);
    const RunArrays<N> a = arrays<N>(m, run, mats, rest, out, O != Order::Vertex);
    const float* const* M = a.M;
    const float* const* W = a.W;
    each_block_avx512<O>(m, run, rest, out, xyz, [&](uint32_t b, __mmask16 k, __m512 x, __m512 y, __m512 z, __m512& px, __m512& py, __m512& pz) SSC_INLINE_LAMBDA {
        __m512 w[N];
        for (int i = 0; i < N; ++i) w[i] = _mm512_maskz_loadu_ps(k, W[i] + b);
        auto blend = [&](int e) SSC_INLINE_LAMBDA {
            __m512 acc = _mm512_mul_ps(w[0], _mm512_set1_ps(M[0][e]));
            for (int i = 1; i < N; ++i) acc = _mm512_fmadd_ps(w[i], _mm512_set1_ps(M[i][e]), acc);
            return acc;
        };
        auto row = [&](const int* e) SSC_INLINE_LAMBDA {
            const __m512 p = _mm512_fmadd_ps(blend(e[2]), z, _mm512_mul_ps(blend(e[0]), x));
            const __m512 c = _mm512_fmadd_ps(blend(e[1]), y, blend(e[3]));
            return _mm512_add_ps(p, c);
        };
        px = row(kRowX), py = row(kRowY), pz = row(kRowZ);
    });
}
SSC_TARGET_END
#endif

#if defined(__wasm_simd128__)
// WebAssembly SIMD (the browser runtime): the AVX2 path's blocks as two 4-lane halves, a multiply
// and an add where it fuses them (see madd.hpp).
template <int N>
void skin_run_wasm(const SkinLayout& m, const SkinLayout::Run& run, const float* mats, const float* rest, float* out, bool slots, float* xyz) {
    const RunArrays<N> a = arrays<N>(m, run, mats, rest, out, slots);
    const float *xs = a.xs, *ys = a.ys, *zs = a.zs;
    float *ox = a.ox, *oy = a.oy, *oz = a.oz;
    const float* const* M = a.M;
    const float* const* W = a.W;
    const uint32_t* vid = m.vertices.data();
    auto madd4 = [](v128_t x, v128_t y, v128_t z) { return wasm_f32x4_add(wasm_f32x4_mul(x, y), z); };
    for (uint32_t b = run.begin; b < run.end; b += 4) {
        const bool contiguous = slots || m.contiguous[b / SkinLayout::kBlock];
        const uint32_t* id = vid + b;
        const uint32_t v0 = slots ? b : id[0];
        v128_t x, y, z;
        if (contiguous) {
            x = wasm_v128_load(xs + v0);
            y = wasm_v128_load(ys + v0);
            z = wasm_v128_load(zs + v0);
        } else {
            x = wasm_f32x4_make(xs[id[0]], xs[id[1]], xs[id[2]], xs[id[3]]);
            y = wasm_f32x4_make(ys[id[0]], ys[id[1]], ys[id[2]], ys[id[3]]);
            z = wasm_f32x4_make(zs[id[0]], zs[id[1]], zs[id[2]], zs[id[3]]);
        }
        v128_t w[N];
        for (int i = 0; i < N; ++i) w[i] = wasm_v128_load(W[i] + b);
        auto blend = [&](int e) SSC_INLINE_LAMBDA {
            v128_t acc = wasm_f32x4_mul(w[0], wasm_f32x4_splat(M[0][e]));
            for (int i = 1; i < N; ++i) acc = madd4(w[i], wasm_f32x4_splat(M[i][e]), acc);
            return acc;
        };
        auto row = [&](const int* e) SSC_INLINE_LAMBDA {
            return wasm_f32x4_add(madd4(blend(e[2]), z, wasm_f32x4_mul(blend(e[0]), x)), madd4(blend(e[1]), y, blend(e[3])));
        };
        const v128_t px = row(kRowX), py = row(kRowY), pz = row(kRowZ);
        if (contiguous) {
            wasm_v128_store(ox + v0, px);
            wasm_v128_store(oy + v0, py);
            wasm_v128_store(oz + v0, pz);
        } else {
            alignas(16) float tx[4], ty[4], tz[4];
            wasm_v128_store(tx, px);
            wasm_v128_store(ty, py);
            wasm_v128_store(tz, pz);
            for (int l = 0; l < 4; ++l) ox[id[l]] = tx[l], oy[id[l]] = ty[l], oz[id[l]] = tz[l];
        }
        if (xyz) {
            alignas(16) float tx[4], ty[4], tz[4];
            wasm_v128_store(tx, px);
            wasm_v128_store(ty, py);
            wasm_v128_store(tz, pz);
            for (int l = 0; l < 4; ++l) {
                float* p = xyz + 3 * std::size_t(id[l]);
                p[0] = tx[l], p[1] = ty[l], p[2] = tz[l];
            }
        }
    }
}
#endif

template <int N>
void skin_run(const SkinLayout& m, const SkinLayout::Run& run, const float* mats, const float* rest, float* out, Isa isa, bool slots, float* xyz) {
#ifdef SSC_SKIN_AVX2
    // (one instantiation per order: nothing left for the compiler to unswitch, and skinning alone
    // compiles as if the xyz writes did not exist)
    if (isa == Isa::Avx512) {
        if (!slots) return skin_run_avx512<N, Order::Vertex>(m, run, mats, rest, out, nullptr);
        if (!xyz) return skin_run_avx512<N, Order::Slots>(m, run, mats, rest, out, nullptr);
        return skin_run_avx512<N, Order::SlotsAndXyz>(m, run, mats, rest, out, xyz);
    }
    if (isa != Isa::Baseline) {
        if (!slots) return skin_run_avx2<N, Order::Vertex>(m, run, mats, rest, out, nullptr);
        if (!xyz) return skin_run_avx2<N, Order::Slots>(m, run, mats, rest, out, nullptr);
        return skin_run_avx2<N, Order::SlotsAndXyz>(m, run, mats, rest, out, xyz);
    }
#endif
#if defined(__wasm_simd128__)
    return skin_run_wasm<N>(m, run, mats, rest, out, slots, xyz);
#endif
    (void)isa;
    skin_run_scalar<N>(m, run, mats, rest, out, slots, xyz);
}

void skin_runs(const SkinLayout& layout, const float* rest, const SkinMatrix* skinning, float* out, uint32_t first, uint32_t end, Isa isa,
               bool slots, float* xyz = nullptr) {
    if (int(isa) > int(supported_isa())) isa = supported_isa();
    const float* mats = skinning[0].m;
    for (const auto& full : layout.runs) {
        if (full.end <= first || full.begin >= end) continue;
        SkinLayout::Run run = full;
        run.begin = std::max(run.begin, first);
        run.end = std::min(run.end, end);
        switch (run.influences) {
            case 1: skin_run<1>(layout, run, mats, rest, out, isa, slots, xyz); break;
            case 2: skin_run<2>(layout, run, mats, rest, out, isa, slots, xyz); break;
            case 3: skin_run<3>(layout, run, mats, rest, out, isa, slots, xyz); break;
            default: skin_run<4>(layout, run, mats, rest, out, isa, slots, xyz); break;
        }
    }
}

}  // namespace

void skin(const Model& m, const float* rest, const SkinMatrix* skinning, float* out) {
    if (skin_by_blocks(active_isa())) return skin_blocks(m.skin_blocks(), rest, skinning, out, nullptr, 0, m.skin_blocks().block_count(), Isa::Avx512);
    skin_slots(m.skin_layout(), rest, skinning, out, 0, m.skin_layout().slot_count(), active_isa());
}

uint32_t skin_slot_count(const Model& m) { return m.skin_layout().slot_count(); }

void skin_slots(const Model& m, const float* rest, const SkinMatrix* skinning, float* out, uint32_t first, uint32_t end) {
    skin_slots(m.skin_layout(), rest, skinning, out, first, end, active_isa());
}

void skin_slots(const Model& m, const float* rest, const SkinMatrix* skinning, float* out, uint32_t first, uint32_t end, Isa isa) {
    skin_slots(m.skin_layout(), rest, skinning, out, first, end, isa);
}

void skin_slots(const SkinLayout& layout, const float* rest, const SkinMatrix* skinning, float* out, uint32_t first, uint32_t end, Isa isa) {
    skin_runs(layout, rest, skinning, out, first, end, isa, /*slots=*/false);
}

void skin_slots_in_slot_order(const SkinLayout& layout, const float* rest_slots, const SkinMatrix* skinning, float* out_slots, uint32_t first,
                              uint32_t end, Isa isa) {
    skin_runs(layout, rest_slots, skinning, out_slots, first, end, isa, /*slots=*/true);
}

void skin_slots_and_xyz(const SkinLayout& layout, const float* rest_slots, const SkinMatrix* skinning, float* out_slots, float* xyz,
                        uint32_t first, uint32_t end, Isa isa) {
    skin_runs(layout, rest_slots, skinning, out_slots, first, end, isa, /*slots=*/true, xyz);
}

void normals(const Model& m, const float* planar, float* face, float* out) {
    face_normals(m, planar, face, 0, m.triangle_count());
    vertex_normals(m, face, out, 0, m.vertex_count());
}

void face_normals(const Model& m, const float* planar, float* face, uint32_t first, uint32_t end) {
    const uint32_t V = m.vertex_count();
    const uint32_t* tris = m.data().mesh.triangles.data();
    const float* X = planar;
    const float* Y = planar + V;
    const float* Z = planar + 2 * std::size_t(V);
    for (uint32_t t = first; t < end; ++t) {
        const uint32_t a = tris[3 * t], b = tris[3 * t + 1], c = tris[3 * t + 2];
        const float e1[3] = {X[b] - X[a], Y[b] - Y[a], Z[b] - Z[a]};
        const float e2[3] = {X[c] - X[a], Y[c] - Y[a], Z[c] - Z[a]};
        // Length = twice the area: area weighting for free.
        float* n = face + 3 * std::size_t(t);
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    }
}

void vertex_normals(const Model& m, const float* face, float* out, uint32_t first, uint32_t end) {
    const uint32_t* off = m.vertex_triangle_offsets();
    const uint32_t* vt = m.vertex_triangles();
    for (uint32_t v = first; v < end; ++v) {
        float n[3] = {0.f, 0.f, 0.f};
        for (uint32_t e = off[v]; e < off[v + 1]; ++e) {
            const float* f = face + 3 * std::size_t(vt[e]);
            n[0] += f[0];
            n[1] += f[1];
            n[2] += f[2];
        }
        const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        float* o = out + 3 * std::size_t(v);
        if (len > 0) {
            const float inv = 1.f / len;
            o[0] = n[0] * inv;
            o[1] = n[1] * inv;
            o[2] = n[2] * inv;
        } else {  // a vertex on no triangle, or on degenerate ones only: any unit vector
            o[0] = 0.f;
            o[1] = 1.f;
            o[2] = 0.f;
        }
    }
}

void landmarks(const format::ModelData& d, const float* planar, float* out, std::size_t stride) {
    const uint32_t V = d.vertex_count();
    auto* base = reinterpret_cast<unsigned char*>(out);
    for (std::size_t l = 0; l < d.landmarks.size(); ++l) {
        const auto& lm = d.landmarks[l];
        float* p = reinterpret_cast<float*>(base + l * stride);
        for (int a = 0; a < 3; ++a) {
            const float* c = planar + std::size_t(a) * V;
            if (lm.vertex != format::kNone) {
                p[a] = c[lm.vertex];
            } else {
                const uint32_t* t = &d.mesh.triangles[3 * lm.triangle];
                p[a] = lm.barycentric[0] * c[t[0]] + lm.barycentric[1] * c[t[1]] + lm.barycentric[2] * c[t[2]];
            }
        }
    }
}

}  // namespace ssc::kernels
