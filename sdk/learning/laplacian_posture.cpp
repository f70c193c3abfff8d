#include "learning/laplacian_posture.hpp"

#include "common/error.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <map>

namespace ssc::learning {

namespace {

// For S = sum w a b^T, the rotation R minimising sum w |b - R a|^2 (Kabsch; no reflection).
Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& S) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d v = svd.matrixV();
    if ((v * svd.matrixU().transpose()).determinant() < 0) v.col(2) = -v.col(2);
    return v * svd.matrixU().transpose();
}

}  // namespace

LaplacianPosture::LaplacianPosture(const Model& model, const LaplacianPostureOptions& options) : options_(options) {
    SSC_REQUIRE_ARG(std::isfinite(options.posture) && options.posture >= 0 && options.posture <= 1e6, "laplacian posture: the posture weight must lie in [0, 1e6]");
    SSC_REQUIRE_ARG(std::isfinite(options.anchor) && options.anchor > 0 && options.anchor <= 1, "laplacian posture: the anchor must lie in (0, 1]");
    SSC_REQUIRE_ARG(options.max_iterations >= 1 && options.max_iterations <= 10000, "laplacian posture: iterations must lie in [1, 10000]");
    SSC_REQUIRE_ARG(std::isfinite(options.tolerance) && options.tolerance > 0, "laplacian posture: the tolerance must be positive");
    const auto& data = model.data();
    const uint32_t V = model.vertex_count();
    auto mean = [&](uint32_t v) { return Eigen::Vector3d(data.shape.mean[3 * std::size_t(v)], data.shape.mean[3 * std::size_t(v) + 1], data.shape.mean[3 * std::size_t(v) + 2]); };

    // Cotangent weights and vertex areas of the mean at rest.
    std::map<std::pair<uint32_t, uint32_t>, double> cot;
    std::vector<double> area(V, 0.0);
    const auto& tri = data.mesh.triangles;
    for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
        const uint32_t idx[3] = {tri[t], tri[t + 1], tri[t + 2]};
        const Eigen::Vector3d p[3] = {mean(idx[0]), mean(idx[1]), mean(idx[2])};
        const double a = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
        for (int k = 0; k < 3; ++k) {
            area[idx[k]] += a / 3;
            // The angle at corner k faces the edge between the other two.
            const Eigen::Vector3d u = p[(k + 1) % 3] - p[k], w = p[(k + 2) % 3] - p[k];
            const double s = u.cross(w).norm();
            const double c = s > 0 ? u.dot(w) / s : 0.0;
            const uint32_t i = idx[(k + 1) % 3], j = idx[(k + 2) % 3];
            cot[{std::min(i, j), std::max(i, j)}] += 0.5 * c;
        }
    }
    // Obtuse triangles give negative cotangents; a floor keeps every edge pulling (and the
    // system positive definite).
    std::vector<std::vector<std::pair<uint32_t, double>>> ring(V);
    for (const auto& [edge, c] : cot) {
        const double w = std::max(c, 1e-2);
        ring[edge.first].push_back({edge.second, w});
        ring[edge.second].push_back({edge.first, w});
    }
    double mean_area = 0;
    for (double a : area) mean_area += a / V;
    SSC_REQUIRE_ARG(mean_area > 0, "laplacian posture: the model's mean has no area");

    first_.assign(1, 0);
    std::vector<Eigen::Triplet<double>> entries;
    anchor_weight_.resize(V);
    mean_.resize(V, 3);
    segment_count_ = model.joint_count();
    skin_weight_.assign(data.skin.weights.begin(), data.skin.weights.end());
    skin_joint_.assign(data.skin.joints.begin(), data.skin.joints.end());
    SSC_REQUIRE_ARG(skin_weight_.size() == 4 * std::size_t(V) && skin_joint_.size() == 4 * std::size_t(V), "laplacian posture: the model's skin is not 4 weights per vertex");
    for (uint32_t j : skin_joint_) SSC_REQUIRE_ARG(j < segment_count_, "laplacian posture: the model's skin names a joint it does not have");
    for (uint32_t i = 0; i < V; ++i) {
        double diagonal = options.anchor * area[i] / mean_area;
        mean_.row(i) = mean(i).transpose();
        anchor_weight_[i] = diagonal;
        for (const auto& [j, w] : ring[i]) {
            neighbour_.push_back(j);
            weight_.push_back(w);
            entries.emplace_back(i, j, -2 * w);
            diagonal += 2 * w;
        }
        entries.emplace_back(i, i, diagonal);
        first_.push_back(uint32_t(neighbour_.size()));
    }
    Eigen::SparseMatrix<double> A(V, V);
    A.setFromTriplets(entries.begin(), entries.end());
    solver_ = std::make_unique<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>(A);
    SSC_REQUIRE_ARG(solver_->info() == Eigen::Success, "laplacian posture: the system of the model's mean could not be factorised");
}

LaplacianPosture::~LaplacianPosture() = default;

std::vector<Eigen::Vector3d> LaplacianPosture::unpose(const std::vector<Eigen::Vector3d>& posed) const {
    const std::size_t V = first_.size() - 1;
    SSC_REQUIRE_ARG_S(posed.size() == V, "laplacian posture: " << posed.size() << " vertices, the model has " << V);
    for (const auto& y : posed) SSC_REQUIRE_ARG(y.allFinite(), "laplacian posture: a registered vertex is not finite");
    // Each skinning segment's rotation onto the mean's (Kabsch, weighted by the skin weights).
    const std::size_t J = segment_count_;
    std::vector<double> mass(J, 0.0);
    std::vector<Eigen::Vector3d> cy(J, Eigen::Vector3d::Zero()), cm(J, Eigen::Vector3d::Zero());
    for (std::size_t i = 0; i < V; ++i)
        for (int k = 0; k < 4; ++k) {
            const double w = skin_weight_[4 * i + std::size_t(k)];
            const uint32_t j = skin_joint_[4 * i + std::size_t(k)];
            mass[j] += w, cy[j] += w * posed[i], cm[j] += w * mean_.row(Eigen::Index(i)).transpose();
        }
    std::vector<Eigen::Matrix3d> C(J, Eigen::Matrix3d::Zero()), Q(J, Eigen::Matrix3d::Identity());
    for (std::size_t j = 0; j < J; ++j)
        if (mass[j] > 0) cy[j] /= mass[j], cm[j] /= mass[j];
    for (std::size_t i = 0; i < V; ++i)
        for (int k = 0; k < 4; ++k) {
            const double w = skin_weight_[4 * i + std::size_t(k)];
            const uint32_t j = skin_joint_[4 * i + std::size_t(k)];
            C[j] += w * (posed[i] - cy[j]) * (mean_.row(Eigen::Index(i)).transpose() - cm[j]).transpose();
        }
    for (std::size_t j = 0; j < J; ++j)
        if (mass[j] > 0) Q[j] = nearest_rotation(C[j]);
    // Each vertex's frame target T_i: its segments' rotations blended by the skin weights.
    std::vector<Eigen::Matrix3d> target(V);
    for (std::size_t i = 0; i < V; ++i) {
        Eigen::Matrix3d blend = Eigen::Matrix3d::Zero();
        for (int k = 0; k < 4; ++k) blend += skin_weight_[4 * i + std::size_t(k)] * Q[skin_joint_[4 * i + std::size_t(k)]];
        target[i] = nearest_rotation(blend.transpose());
    }
    // Start from the mean at rest.
    Eigen::MatrixX3d x = mean_;
    std::vector<Eigen::Matrix3d> R(V);
    Eigen::MatrixX3d b(V, 3);
    for (uint32_t iteration = 0; iteration < options_.max_iterations; ++iteration) {
        // Frames: each vertex's rotation taking the registration's one ring onto x's, drawn
        // towards its target (the rotation nearest S + posture * s_i * T_i^T).
        for (std::size_t i = 0; i < V; ++i) {
            Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
            double size = 0;
            for (uint32_t k = first_[i]; k < first_[i + 1]; ++k) {
                const uint32_t j = neighbour_[k];
                S += weight_[k] * (posed[i] - posed[j]) * (x.row(Eigen::Index(i)) - x.row(Eigen::Index(j)));
                size += weight_[k] * (posed[i] - posed[j]).squaredNorm();
            }
            R[i] = nearest_rotation(S + options_.posture * size * target[i].transpose());
        }
        // Positions: (2L + anchor M) x = sum_j w_ij (R_i + R_j)(y_i - y_j) + anchor M mu.
        b = mean_.array().colwise() * Eigen::Map<const Eigen::ArrayXd>(anchor_weight_.data(), Eigen::Index(V));
        for (std::size_t i = 0; i < V; ++i)
            for (uint32_t k = first_[i]; k < first_[i + 1]; ++k) {
                const uint32_t j = neighbour_[k];
                b.row(Eigen::Index(i)) += (weight_[k] * (R[i] + R[j]) * (posed[i] - posed[j])).transpose();
            }
        const Eigen::MatrixX3d next = solver_->solve(b);
        const double moved = (next - x).rowwise().norm().maxCoeff();
        x = next;
        if (moved < options_.tolerance) break;
    }
    std::vector<Eigen::Vector3d> rest(V);
    for (std::size_t i = 0; i < V; ++i) rest[i] = x.row(Eigen::Index(i)).transpose();
    return rest;
}

}  // namespace ssc::learning
