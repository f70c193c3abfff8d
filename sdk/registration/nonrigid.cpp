#include "registration/nonrigid.hpp"

#include "common/error.hpp"

#include <algorithm>

namespace ssc::registration {

namespace {
// Weight of the anchor that keeps the system definite (see NonrigidSystem::solve): far below any
// data, landmark or smoothness term a registration uses.
constexpr double kAnchor = 1e-9;
}  // namespace

std::vector<std::array<uint32_t, 2>> mesh_edges(const std::vector<uint32_t>& triangles, uint32_t vertex_count) {
    std::vector<std::array<uint32_t, 2>> edges;
    edges.reserve(triangles.size());
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = triangles[t + std::size_t(e)], b = triangles[t + std::size_t((e + 1) % 3)];
            SSC_REQUIRE_ARG(a < vertex_count && b < vertex_count, "mesh_edges: a triangle index is out of range");
            if (a != b) edges.push_back({std::min(a, b), std::max(a, b)});
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    return edges;
}

NonrigidSystem::NonrigidSystem(std::vector<Vector3d> vertices, std::vector<std::array<uint32_t, 2>> edges,
                               std::vector<double> edge_stiffness, const std::vector<TemplatePoint>& landmark_points, double gamma)
    : p_(std::move(vertices)), edges_(std::move(edges)), edge_stiffness_(std::move(edge_stiffness)) {
    const std::size_t N = p_.size();
    SSC_REQUIRE_ARG(N >= 3, "registration: the template needs at least 3 vertices");
    SSC_REQUIRE_ARG(std::isfinite(gamma) && gamma > 0, "registration: gamma must be positive");
    if (edge_stiffness_.empty()) edge_stiffness_.assign(edges_.size(), 1.0);
    SSC_REQUIRE_ARG(edge_stiffness_.size() == edges_.size(), "registration: one stiffness per edge");
    centre_ = Vector3d::Zero();
    for (const Vector3d& v : p_) centre_ += v;
    centre_ /= double(N);
    for (Vector3d& v : p_) v -= centre_;
    g2_ = Eigen::Vector4d(1, 1, 1, gamma * gamma);
    // The structure: every vertex's 4x4 block, each edge's diagonal entries both ways, and full
    // blocks among the vertices of each landmark point.
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(16 * N + 8 * edges_.size());
    auto block = [&](uint32_t i, uint32_t j) {
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) t.emplace_back(4 * int(i) + a, 4 * int(j) + b, 0.0);
    };
    for (uint32_t v = 0; v < N; ++v) block(v, v);
    for (const auto& e : edges_) {
        SSC_REQUIRE_ARG(e[0] < N && e[1] < N && e[0] != e[1], "registration: an edge is out of range");
        for (int a = 0; a < 4; ++a) {
            t.emplace_back(4 * int(e[0]) + a, 4 * int(e[1]) + a, 0.0);
            t.emplace_back(4 * int(e[1]) + a, 4 * int(e[0]) + a, 0.0);
        }
    }
    for (const TemplatePoint& lp : landmark_points)
        for (int m = 0; m < 3; ++m)
            for (int n = 0; n < 3; ++n) {
                SSC_REQUIRE_ARG(lp.vertex[m] < N && lp.vertex[n] < N, "registration: a landmark vertex is out of range");
                if (m != n && lp.weight[m] != 0 && lp.weight[n] != 0) block(lp.vertex[m], lp.vertex[n]);
            }
    pattern_.resize(Eigen::Index(4 * N), Eigen::Index(4 * N));
    pattern_.setFromTriplets(t.begin(), t.end());
    pattern_.makeCompressed();
    cholesky_.analyze(pattern_);
    // Where the terms every assembly adds go: a block's four rows are adjacent in each column.
    block_column_.resize(4 * N);
    for (uint32_t v = 0; v < N; ++v)
        for (int b = 0; b < 4; ++b) block_column_[4 * v + std::size_t(b)] = offset(4 * Eigen::Index(v), 4 * Eigen::Index(v) + b);
    edge_offset_.resize(edges_.size());
    for (std::size_t e = 0; e < edges_.size(); ++e) {
        const Eigen::Index i = 4 * Eigen::Index(edges_[e][0]), j = 4 * Eigen::Index(edges_[e][1]);
        for (int a = 0; a < 4; ++a) edge_offset_[e][std::size_t(a)] = offset(i + a, j + a), edge_offset_[e][std::size_t(4 + a)] = offset(j + a, i + a);
    }
}

std::size_t NonrigidSystem::offset(Eigen::Index row, Eigen::Index col) const {
    const auto* outer = pattern_.outerIndexPtr();
    const auto* inner = pattern_.innerIndexPtr();
    const auto* begin = inner + outer[col];
    const auto* end = inner + outer[col + 1];
    const auto* it = std::lower_bound(begin, end, int(row));
    if (it == end || *it != row) fail(SSC_ERROR_INTERNAL, "registration: an entry outside the system's structure");
    return std::size_t(it - inner);
}

Eigen::MatrixX3d NonrigidSystem::identity() const {
    Eigen::MatrixX3d X = Eigen::MatrixX3d::Zero(Eigen::Index(4 * p_.size()), 3);
    for (std::size_t v = 0; v < p_.size(); ++v) X.block<3, 3>(Eigen::Index(4 * v), 0).setIdentity();
    // X_i = A_i^T for the centred template: A_i = [I, 0] (the centring is undone in deformed()).
    return X;
}

std::vector<Vector3d> NonrigidSystem::deformed(const Eigen::MatrixX3d& X) const {
    std::vector<Vector3d> out(p_.size());
    for (std::size_t v = 0; v < p_.size(); ++v)
        out[v] = X.block<4, 3>(Eigen::Index(4 * v), 0).transpose() * hom(uint32_t(v)) + centre_;
    return out;
}

Vector3d NonrigidSystem::deformed(const Eigen::MatrixX3d& X, const TemplatePoint& p) const {
    Vector3d x = Vector3d::Zero();
    for (int m = 0; m < 3; ++m)
        if (p.weight[m] != 0) x += p.weight[m] * (X.block<4, 3>(4 * Eigen::Index(p.vertex[m]), 0).transpose() * hom(p.vertex[m]));
    return x + centre_;
}

double NonrigidSystem::energy(const Eigen::MatrixX3d& X, const EnergyWeights& k, const std::vector<Vector3d>& targets,
                              const std::vector<double>& weights, const std::vector<LandmarkTarget>& landmarks,
                              const Eigen::MatrixX3d& anchor) const {
    const std::size_t N = p_.size();
    double data = 0, smooth = 0, marks = 0;
    for (std::size_t v = 0; v < N; ++v)
        if (weights[v] != 0)
            data += weights[v] * (X.block<4, 3>(Eigen::Index(4 * v), 0).transpose() * hom(uint32_t(v)) + centre_ - targets[v]).squaredNorm();
    for (std::size_t e = 0; e < edges_.size(); ++e) {
        const Eigen::Matrix<double, 4, 3> d = X.block<4, 3>(4 * Eigen::Index(edges_[e][0]), 0) - X.block<4, 3>(4 * Eigen::Index(edges_[e][1]), 0);
        smooth += edge_stiffness_[e] * (g2_.asDiagonal() * d.cwiseProduct(d)).sum();
    }
    for (const LandmarkTarget& l : landmarks) marks += (deformed(X, l.point) - l.target).squaredNorm();
    const double L = landmarks.empty() ? 1.0 : double(landmarks.size());
    return k.data / double(N) * data + k.stiffness * smooth + k.landmarks / L * marks + kAnchor * (X - anchor).squaredNorm();
}

void NonrigidSystem::assemble(const EnergyWeights& k, const std::vector<Vector3d>& targets, const std::vector<double>& weights,
                              const std::vector<LandmarkTarget>& landmarks, const Eigen::MatrixX3d& anchor,
                              Eigen::SparseMatrix<double>& K, Eigen::MatrixX3d& R) const {
    assemble_matrix(k, weights, landmarks, K);
    R = assemble_rhs(k, targets, weights, landmarks, anchor);
}

// Each term's residual is r = X^T u - y (u: 4 coefficients over some vertices' rows, y a point): it
// adds u u^T into K and u y^T into R, times its weight.
void NonrigidSystem::assemble_matrix(const EnergyWeights& k, const std::vector<double>& weights,
                                     const std::vector<LandmarkTarget>& landmarks, Eigen::SparseMatrix<double>& K) const {
    const std::size_t N = p_.size();
    SSC_REQUIRE_ARG(weights.size() == N, "registration: one weight per template vertex");
    K = pattern_;
    double* value = K.valuePtr();
    std::fill(value, value + K.nonZeros(), 0.0);
    auto add_block = [&](uint32_t i, uint32_t j, const Eigen::Vector4d& ui, const Eigen::Vector4d& uj, double w) {
        for (int b = 0; b < 4; ++b)
            for (int a = 0; a < 4; ++a) value[offset(4 * Eigen::Index(i) + a, 4 * Eigen::Index(j) + b)] += w * ui[a] * uj[b];
    };
    const double data_w = k.data / double(N);
    auto diagonal = [&](std::size_t v, int a) -> double& { return value[block_column_[4 * v + std::size_t(a)] + std::size_t(a)]; };
    for (uint32_t v = 0; v < N; ++v) {
        const Eigen::Vector4d u = hom(v);
        const double w = data_w * weights[v];
        for (int b = 0; b < 4; ++b)
            for (int a = 0; a < 4; ++a) value[block_column_[4 * std::size_t(v) + std::size_t(b)] + std::size_t(a)] += w * u[a] * u[b];
        for (int a = 0; a < 4; ++a) diagonal(v, a) += kAnchor;
    }
    for (std::size_t e = 0; e < edges_.size(); ++e) {
        const double w = k.stiffness * edge_stiffness_[e];
        for (int a = 0; a < 4; ++a) {
            diagonal(edges_[e][0], a) += w * g2_[a];
            diagonal(edges_[e][1], a) += w * g2_[a];
            value[edge_offset_[e][std::size_t(a)]] -= w * g2_[a];
            value[edge_offset_[e][std::size_t(4 + a)]] -= w * g2_[a];
        }
    }
    const double mark_w = landmarks.empty() ? 0.0 : k.landmarks / double(landmarks.size());
    for (const LandmarkTarget& l : landmarks)
        for (int m = 0; m < 3; ++m)
            for (int n = 0; n < 3; ++n)
                if (l.point.weight[m] != 0 && l.point.weight[n] != 0)
                    add_block(l.point.vertex[m], l.point.vertex[n], l.point.weight[m] * hom(l.point.vertex[m]),
                              l.point.weight[n] * hom(l.point.vertex[n]), mark_w);
}

Eigen::MatrixX3d NonrigidSystem::assemble_rhs(const EnergyWeights& k, const std::vector<Vector3d>& targets,
                                              const std::vector<double>& weights, const std::vector<LandmarkTarget>& landmarks,
                                              const Eigen::MatrixX3d& anchor) const {
    const std::size_t N = p_.size();
    SSC_REQUIRE_ARG(targets.size() == N && weights.size() == N, "registration: one target and weight per template vertex");
    SSC_REQUIRE_ARG(anchor.rows() == Eigen::Index(4 * N), "registration: the anchor needs 4 rows per vertex");
    Eigen::MatrixX3d R = kAnchor * anchor;
    const double data_w = k.data / double(N);
    for (uint32_t v = 0; v < N; ++v)
        if (weights[v] != 0) R.block<4, 3>(4 * Eigen::Index(v), 0) += data_w * weights[v] * hom(v) * (targets[v] - centre_).transpose();
    const double mark_w = landmarks.empty() ? 0.0 : k.landmarks / double(landmarks.size());
    for (const LandmarkTarget& l : landmarks)
        for (int m = 0; m < 3; ++m)
            if (l.point.weight[m] != 0)
                R.block<4, 3>(4 * Eigen::Index(l.point.vertex[m]), 0) +=
                    mark_w * l.point.weight[m] * hom(l.point.vertex[m]) * (l.target - centre_).transpose();
    return R;
}

void NonrigidSystem::factorize(const EnergyWeights& k, const std::vector<double>& weights, const std::vector<LandmarkTarget>& landmarks,
                               ThreadPool* pool) {
    Eigen::SparseMatrix<double> K;
    assemble_matrix(k, weights, landmarks, K);
    if (!cholesky_.factorize(K, pool)) fail(SSC_ERROR_INTERNAL, "registration: the deformation system could not be factorised");
    factored_k_ = k;
    factored_weights_ = weights;
    factored_ = true;
}

Eigen::MatrixX3d NonrigidSystem::solve(const std::vector<Vector3d>& targets, const std::vector<LandmarkTarget>& landmarks,
                                       const Eigen::MatrixX3d& anchor, ThreadPool* pool) const {
    if (!factored_) fail(SSC_ERROR_INTERNAL, "registration: solve before factorize");
    return cholesky_.solve(assemble_rhs(factored_k_, targets, factored_weights_, landmarks, anchor), pool);
}

}  // namespace ssc::registration
