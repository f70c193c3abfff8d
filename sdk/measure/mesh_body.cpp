#include "measure/mesh_body.hpp"

#include "common/error.hpp"
#include "common/rigid.hpp"

#include <Eigen/Geometry>
#include <Eigen/QR>

#include <cmath>
#include <string>

namespace ssc::measure {

MeshBody mesh_body(const Model& model, const std::vector<Eigen::Vector3d>& vertices) {
    const uint32_t V = model.vertex_count(), J = model.joint_count();
    SSC_REQUIRE_ARG(vertices.size() == V, "the mesh has " + std::to_string(vertices.size()) + " vertices; the model has " + std::to_string(V) +
                                              " (a body to measure keeps the model's vertices and their order)");
    Eigen::Matrix3Xd src(3, V), dst(3, V);
    const float* mean = model.mean_planar();  // planar: x block, y block, z block
    for (uint32_t v = 0; v < V; ++v) {
        SSC_REQUIRE_ARG(vertices[v].allFinite(), "the mesh's vertex " + std::to_string(v) + " is not finite");
        src.col(v) = vertices[v];
        for (int a = 0; a < 3; ++a) dst(a, v) = mean[std::size_t(a) * V + v];
    }
    // The shape space (dequantized components) and a small rigid motion about the mean.
    const uint32_t K = model.component_count();
    const auto& basis = model.data().shape.basis;
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(3 * Eigen::Index(V), Eigen::Index(K) + 6);
    for (uint32_t k = 0; k < K; ++k)
        for (Eigen::Index r = 0; r < B.rows(); ++r) B(r, k) = double(basis.q[std::size_t(k) * std::size_t(B.rows()) + std::size_t(r)]) * basis.step[k];
    for (uint32_t v = 0; v < V; ++v)
        for (int a = 0; a < 3; ++a) {
            B(Eigen::Index(a) * V + v, K + a) = 1;  // translation along axis a
            const Eigen::Vector3d turn = Eigen::Vector3d::Unit(a).cross(Eigen::Vector3d(dst.col(v)));  // rotation about axis a
            for (int c = 0; c < 3; ++c) B(Eigen::Index(c) * V + v, K + 3 + a) = turn[c];
        }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(B);
    // Aligned onto the mean first, then onto the nearest body of the shape space (a tall body
    // matched to the mean leans a little; matched to its own kind it stands as the model's bodies do).
    MeshBody b;
    b.xyz.resize(3ull * V);
    Eigen::Matrix3Xd target = dst;
    Eigen::VectorXd residual;
    for (int pass = 0; pass < 2; ++pass) {
        const Similarity T = align_points(src, target, false);
        Eigen::VectorXd offset(3 * Eigen::Index(V));  // planar, like the basis
        for (uint32_t v = 0; v < V; ++v) {
            const Eigen::Vector3d p = T.R * src.col(v) + T.t;
            for (int a = 0; a < 3; ++a) {
                b.xyz[3ull * v + std::size_t(a)] = float(p[a]);
                offset[Eigen::Index(a) * V + v] = p[a] - dst(a, v);
            }
        }
        const Eigen::VectorXd coefficients = qr.solve(offset);
        residual = offset - B * coefficients;
        const Eigen::VectorXd shaped = B.leftCols(K) * coefficients.head(K);
        for (uint32_t v = 0; v < V; ++v)
            for (int a = 0; a < 3; ++a) target(a, v) = dst(a, v) + shaped[Eigen::Index(a) * V + v];
    }
    b.off_shape_space = std::sqrt(residual.squaredNorm() / double(V));
    const auto& sk = model.data().skeleton;
    b.joints.assign(3ull * J, 0.f);
    for (uint32_t j = 0; j < J; ++j)
        for (uint32_t e = sk.regressor_offsets[j]; e < sk.regressor_offsets[j + 1]; ++e)
            for (int a = 0; a < 3; ++a) b.joints[3ull * j + std::size_t(a)] += sk.regressor_weights[e] * b.xyz[3ull * sk.regressor_vertices[e] + std::size_t(a)];
    return b;
}

}  // namespace ssc::measure
