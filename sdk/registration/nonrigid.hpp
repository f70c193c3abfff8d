// Non-rigid template deformation (after Amberg, Romdhani and Vetter, "Optimal step nonrigid ICP
// algorithms for surface registration", CVPR 2007): every template vertex p_i gets its own affine
// transform A_i (3x4), and at fixed correspondences the energy
//
//   E = a/N sum_i w_i |A_i p_i - q_i|^2           data: q_i the vertex's scan point, w_i its weight
//     + b sum_(i,j) s_ij |(A_i - A_j) G|_F^2      smoothness over the template's edges, s_ij per edge
//     + c/L sum_l |sum_m beta_lm A_m p_m - t_l|^2  landmarks: a point of the template on target t_l
//
// is quadratic in the transforms: its minimum is one sparse linear solve. G = diag(1, 1, 1, gamma)
// weighs the transforms' translation against their linear part. Why these normalisations: the data
// term is a mean over the N vertices and the smoothness a sum over edges (a Dirichlet energy, which
// does not grow when the mesh is refined), so one set of weights serves any vertex count; the
// template is centred on its centroid, so the translations stay small and gamma means the same for
// any placement. Coordinates are metres.
//
// The unknowns X (4N x 3, X_i = A_i^T) decouple into three right-hand sides of one 4N x 4N matrix
// whose sparsity never changes (each vertex's 4x4 block, each edge's diagonal blocks, the blocks
// among the vertices of the template's landmark triangles): it is analysed once per template and
// only factorised again when the weights change (block_cholesky.hpp).
#pragma once

#include "fitting/kinematics.hpp"
#include "registration/block_cholesky.hpp"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <array>
#include <cstdint>
#include <vector>

namespace ssc::registration {

using Eigen::Vector3d;

// A point of the template: up to three vertices with barycentric weights (a vertex: one weight 1).
using TemplatePoint = fitting::SurfacePoint;

struct LandmarkTarget {
    TemplatePoint point;
    Vector3d target;
};

struct EnergyWeights {
    double data = 1;        // a
    double stiffness = 1;   // b
    double landmarks = 1;   // c
};

// The unique undirected edges of a triangle mesh, each (smaller, larger) index, sorted.
std::vector<std::array<uint32_t, 2>> mesh_edges(const std::vector<uint32_t>& triangles, uint32_t vertex_count);

class NonrigidSystem {
public:
    // The template's start positions (metres), its edges with their stiffness factors s_ij (empty:
    // all 1), and every template point that landmarks may use (the blocks they couple). gamma: G's
    // last entry.
    NonrigidSystem(std::vector<Vector3d> vertices, std::vector<std::array<uint32_t, 2>> edges, std::vector<double> edge_stiffness,
                   const std::vector<TemplatePoint>& landmark_points, double gamma = 1.0);

    uint32_t vertex_count() const { return uint32_t(p_.size()); }
    // The transforms of the undeformed template (A_i = [I 0]).
    Eigen::MatrixX3d identity() const;
    // The deformed template: A_i p_i for every vertex.
    std::vector<Vector3d> deformed(const Eigen::MatrixX3d& X) const;
    // A template point under the transforms.
    Vector3d deformed(const Eigen::MatrixX3d& X, const TemplatePoint& p) const;

    // The energy at X for per-vertex targets and weights (w_i = 0: no data term) and landmarks,
    // plus the anchor (see solve). Each landmark's point must be one given at construction.
    double energy(const Eigen::MatrixX3d& X, const EnergyWeights& k, const std::vector<Vector3d>& targets,
                  const std::vector<double>& weights, const std::vector<LandmarkTarget>& landmarks, const Eigen::MatrixX3d& anchor) const;
    // Its normal equations: E = tr(X^T K X) - 2 tr(X^T R) + const, so dE/dX = 2 (K X - R).
    void assemble(const EnergyWeights& k, const std::vector<Vector3d>& targets, const std::vector<double>& weights,
                  const std::vector<LandmarkTarget>& landmarks, const Eigen::MatrixX3d& anchor, Eigen::SparseMatrix<double>& K,
                  Eigen::MatrixX3d& R) const;

    // The minimiser in two steps: K depends on the weights and which landmarks there are, not on
    // the targets, so one factorisation serves every solve until the weights change. A tiny anchor
    // term (1e-9 |X - anchor|^2) keeps the system definite where nothing else holds the
    // transforms (no data and no landmarks). factorize throws ssc::Error (INTERNAL) should that
    // fail; solve uses the last factorisation's weights and landmark points. With a pool both
    // use its threads (block_cholesky.hpp); the results are the same without.
    void factorize(const EnergyWeights& k, const std::vector<double>& weights, const std::vector<LandmarkTarget>& landmarks,
                   ThreadPool* pool = nullptr);
    Eigen::MatrixX3d solve(const std::vector<Vector3d>& targets, const std::vector<LandmarkTarget>& landmarks,
                           const Eigen::MatrixX3d& anchor, ThreadPool* pool = nullptr) const;

private:
    Eigen::Vector4d hom(uint32_t v) const { return Eigen::Vector4d(p_[v].x(), p_[v].y(), p_[v].z(), 1.0); }
    // Offset of entry (row, col) in the pattern's values.
    std::size_t offset(Eigen::Index row, Eigen::Index col) const;

    std::vector<Vector3d> p_;  // centred template vertices
    Vector3d centre_;
    std::vector<std::array<uint32_t, 2>> edges_;
    std::vector<double> edge_stiffness_;
    Eigen::Vector4d g2_;  // G^2's diagonal
    void assemble_matrix(const EnergyWeights& k, const std::vector<double>& weights, const std::vector<LandmarkTarget>& landmarks,
                         Eigen::SparseMatrix<double>& K) const;
    Eigen::MatrixX3d assemble_rhs(const EnergyWeights& k, const std::vector<Vector3d>& targets, const std::vector<double>& weights,
                                  const std::vector<LandmarkTarget>& landmarks, const Eigen::MatrixX3d& anchor) const;

    Eigen::SparseMatrix<double> pattern_;  // the matrix's structure (values overwritten per assembly)
    std::vector<std::size_t> block_column_;  // per vertex and column b of its block: where row 0 of it is
    std::vector<std::array<std::size_t, 8>> edge_offset_;  // per edge (i, j): entries (i+a, j+a), then (j+a, i+a)
    EnergyWeights factored_k_;             // what the factorisation was made with
    std::vector<double> factored_weights_;
    bool factored_ = false;
    BlockCholesky4 cholesky_;
};

}  // namespace ssc::registration
