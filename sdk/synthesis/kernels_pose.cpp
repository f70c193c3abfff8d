// Skeleton and skinning stages.
//
// Joint j has rest world position p_j (from the shape) and rest local orientation R_j. Its rest
// world rotation is W_j = W_parent * R_j, and its offset in the parent's frame is
// o_j = W_parent^T (p_j - p_parent). Posed: G_j = G_parent * [R_j * P_j | o_j], with P_j the pose
// rotation; the root is [R_root * P_root | p_root + translation]. The bind transform is
// [W_j | p_j], and skinning uses G_j * bind_j^-1, which is the identity in the zero pose.
#include "kernels.hpp"
#include "model.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <cstring>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define SSC_SKIN_AVX2 1
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

void skeleton(const Model& m, const float* joints_rest, const float* quats, const float* translation, float* scratch,
              float* world16, float* inverse_bind16, SkinMatrix* skinning) {
    const uint32_t J = m.joint_count();
    const auto& sk = m.data().skeleton;
    // Per joint: rest world rotation W, posed world rotation G and translation Gt (9 + 9 + 3 floats).
    using Map3 = Eigen::Map<Matrix3f>;
    using MapV = Eigen::Map<Vector3f>;
    auto W = [&](uint32_t j) { return Map3(scratch + 21 * std::size_t(j)); };
    auto G = [&](uint32_t j) { return Map3(scratch + 21 * std::size_t(j) + 9); };
    auto Gt = [&](uint32_t j) { return MapV(scratch + 21 * std::size_t(j) + 18); };
    for (uint32_t j = 0; j < J; ++j) {
        const float* rq = &sk.rest_orientations[4 * j];
        const Matrix3f R = Eigen::Quaternionf(rq[3], rq[0], rq[1], rq[2]).normalized().toRotationMatrix();
        const float* pq = quats + 4 * j;
        const Matrix3f P = Eigen::Quaternionf(pq[3], pq[0], pq[1], pq[2]).toRotationMatrix();
        const Vector3f p(joints_rest + 3 * j);
        const int32_t parent = sk.parents[j];
        if (parent < 0) {
            W(j) = R;
            G(j) = R * P;
            Gt(j) = p + Vector3f(translation);
        } else {
            const auto up = static_cast<uint32_t>(parent);
            const Vector3f offset = W(up).transpose() * (p - Vector3f(joints_rest + 3 * up));
            W(j) = W(up) * R;
            G(j) = G(up) * (R * P);
            Gt(j) = G(up) * offset + Gt(up);
        }
        // Bind inverse: [W^T | -W^T p].
        const Matrix3f Wt = W(j).transpose();
        const Vector3f bt = -(Wt * p);
        if (world16) store16(G(j), Gt(j), world16 + 16 * j);
        if (inverse_bind16) store16(Wt, bt, inverse_bind16 + 16 * j);
        if (skinning) store16(G(j) * Wt, G(j) * bt + Gt(j), skinning[j].m);
    }
}

namespace {

// Skins the vertices that have exactly N influences. The blend accumulates w_0 M_0 + w_1 M_1 + ...
// with FMAs, then transforms: p = (c0 x + c2 z) + (c1 y + c3), the same order in both paths.
template <int N>
void skin_group(const Model::SkinGroup& g, const float* xs, const float* ys, const float* zs, const float* mats,
                float* out) {
    const std::size_t n = g.vertices.size();
    const uint32_t* off = g.offsets.data();
    const float* w = g.weights.data();
#ifdef SSC_SKIN_AVX2
    for (std::size_t i = 0; i < n; ++i, off += N, w += N) {
        const uint32_t v = g.vertices[i];
        const __m256 w0 = _mm256_broadcast_ss(w);
        __m256 lo = _mm256_mul_ps(w0, _mm256_load_ps(mats + off[0]));
        __m256 hi = _mm256_mul_ps(w0, _mm256_load_ps(mats + off[0] + 8));
        for (int k = 1; k < N; ++k) {
            const __m256 wk = _mm256_broadcast_ss(w + k);
            lo = _mm256_fmadd_ps(wk, _mm256_load_ps(mats + off[k]), lo);
            hi = _mm256_fmadd_ps(wk, _mm256_load_ps(mats + off[k] + 8), hi);
        }
        const __m256 xy = _mm256_set_m128(_mm_set1_ps(ys[v]), _mm_set1_ps(xs[v]));
        const __m256 z1 = _mm256_set_m128(_mm_set1_ps(1.f), _mm_set1_ps(zs[v]));
        const __m256 r = _mm256_fmadd_ps(hi, z1, _mm256_mul_ps(lo, xy));
        const __m128 p = _mm_add_ps(_mm256_castps256_ps128(r), _mm256_extractf128_ps(r, 1));
        float* o = out + 3 * std::size_t(v);
        _mm_storel_pi(reinterpret_cast<__m64*>(o), p);  // x, y
        _mm_store_ss(o + 2, _mm_movehl_ps(p, p));       // z: exactly 12 bytes, vertices are not in order
    }
#else
    for (std::size_t i = 0; i < n; ++i, off += N, w += N) {
        const uint32_t v = g.vertices[i];
        float b[16];
        for (int e = 0; e < 16; ++e) b[e] = w[0] * mats[off[0] + e];
        for (int k = 1; k < N; ++k)
            for (int e = 0; e < 16; ++e) b[e] = std::fma(w[k], mats[off[k] + e], b[e]);
        for (int a = 0; a < 3; ++a)
            out[3 * std::size_t(v) + a] = std::fma(b[8 + a], zs[v], b[a] * xs[v]) + std::fma(b[12 + a], 1.f, b[4 + a] * ys[v]);
    }
#endif
}

}  // namespace

void skin(const Model& m, const float* rest, const SkinMatrix* skinning, float* out) {
    const uint32_t V = m.vertex_count();
    const float* mats = skinning[0].m;
    const float* xs = rest;
    const float* ys = rest + V;
    const float* zs = rest + 2 * std::size_t(V);
    skin_group<1>(m.skin_group(1), xs, ys, zs, mats, out);
    skin_group<2>(m.skin_group(2), xs, ys, zs, mats, out);
    skin_group<3>(m.skin_group(3), xs, ys, zs, mats, out);
    skin_group<4>(m.skin_group(4), xs, ys, zs, mats, out);
}

void normals(const Model& m, const float* xyz, float* face, float* out) {
    const uint32_t V = m.vertex_count(), T = m.triangle_count();
    const uint32_t* tris = m.data().mesh.triangles.data();
    for (uint32_t t = 0; t < T; ++t) {
        const float* a = xyz + 3 * std::size_t(tris[3 * t]);
        const float* b = xyz + 3 * std::size_t(tris[3 * t + 1]);
        const float* c = xyz + 3 * std::size_t(tris[3 * t + 2]);
        const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        // Length = twice the area: area weighting for free.
        float* n = face + 3 * std::size_t(t);
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    }
    const uint32_t* off = m.vertex_triangle_offsets();
    const uint32_t* vt = m.vertex_triangles();
    for (uint32_t v = 0; v < V; ++v) {
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

void landmarks(const format::ModelData& d, const float* xyz, float* out, std::size_t stride) {
    auto* base = reinterpret_cast<unsigned char*>(out);
    for (std::size_t l = 0; l < d.landmarks.size(); ++l) {
        const auto& lm = d.landmarks[l];
        float* p = reinterpret_cast<float*>(base + l * stride);
        if (lm.vertex != format::kNone) {
            for (int a = 0; a < 3; ++a) p[a] = xyz[3 * lm.vertex + a];
        } else {
            const uint32_t* t = &d.mesh.triangles[3 * lm.triangle];
            for (int a = 0; a < 3; ++a)
                p[a] = lm.barycentric[0] * xyz[3 * t[0] + a] + lm.barycentric[1] * xyz[3 * t[1] + a] +
                       lm.barycentric[2] * xyz[3 * t[2] + a];
        }
    }
}

}  // namespace ssc::kernels
