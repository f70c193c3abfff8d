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

#include <cstring>

namespace ssc::kernels {
namespace {

using Eigen::Matrix3f;
using Eigen::Vector3f;
using MapV = Eigen::Map<Vector3f>;

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
              float* world16, float* inverse_bind16, Affine34* skinning) {
    const uint32_t J = m.joint_count();
    const auto& sk = m.data().skeleton;
    // Per joint: rest world rotation W, posed world rotation G and translation Gt (9 + 9 + 3 floats).
    using Map3 = Eigen::Map<Matrix3f>;
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
        if (skinning) {
            const Matrix3f S = G(j) * Wt;
            const Vector3f St = G(j) * bt + Gt(j);
            float* o = skinning[j].m;
            for (int row = 0; row < 3; ++row) {
                o[row * 4 + 0] = S(row, 0);
                o[row * 4 + 1] = S(row, 1);
                o[row * 4 + 2] = S(row, 2);
                o[row * 4 + 3] = St(row);
            }
        }
    }
}

void skin(const Model& m, const float* rest, const Affine34* skinning, float* out, std::size_t stride) {
    const uint32_t V = m.vertex_count();
    const uint16_t* joints = m.data().skin.joints.data();
    const float* weights = m.data().skin.weights.data();
    const float* xs = rest;
    const float* ys = rest + V;
    const float* zs = rest + 2 * std::size_t(V);
    auto* base = reinterpret_cast<unsigned char*>(out);
    for (uint32_t v = 0; v < V; ++v) {
        float b[12];
        const float* m0 = skinning[joints[4 * v]].m;
        const float w0 = weights[4 * v];
        for (int i = 0; i < 12; ++i) b[i] = w0 * m0[i];
        for (int s = 1; s < 4; ++s) {
            const float w = weights[4 * v + s];
            if (w == 0.f) continue;  // most vertices have fewer than 4 influences
            const float* ms = skinning[joints[4 * v + s]].m;
            for (int i = 0; i < 12; ++i) b[i] += w * ms[i];
        }
        const float x = xs[v], y = ys[v], z = zs[v];
        float* p = reinterpret_cast<float*>(base + v * stride);
        p[0] = b[0] * x + b[1] * y + b[2] * z + b[3];
        p[1] = b[4] * x + b[5] * y + b[6] * z + b[7];
        p[2] = b[8] * x + b[9] * y + b[10] * z + b[11];
    }
}

void normals(const Model& m, const float* xyz, std::size_t in_stride, float* out, std::size_t out_stride) {
    const uint32_t V = m.vertex_count();
    const auto* in = reinterpret_cast<const unsigned char*>(xyz);
    auto* ob = reinterpret_cast<unsigned char*>(out);
    auto at = [&](uint32_t v) { return Vector3f(reinterpret_cast<const float*>(in + v * in_stride)); };
    auto acc = [&](uint32_t v) { return MapV(reinterpret_cast<float*>(ob + v * out_stride)); };
    for (uint32_t v = 0; v < V; ++v) acc(v).setZero();
    const auto& tris = m.data().mesh.triangles;
    for (std::size_t t = 0; t + 3 <= tris.size(); t += 3) {
        const uint32_t a = tris[t], b = tris[t + 1], c = tris[t + 2];
        const Vector3f pa = at(a);
        const Vector3f n = (at(b) - pa).cross(at(c) - pa);  // length = 2 x area: area weighting
        acc(a) += n;
        acc(b) += n;
        acc(c) += n;
    }
    for (uint32_t v = 0; v < V; ++v) {
        auto n = acc(v);
        const float len = n.norm();
        if (len > 0) n /= len;
        else n = Vector3f(0, 1, 0);  // a vertex on no triangle (or degenerate ones): any unit vector
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
