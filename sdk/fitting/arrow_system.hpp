// The Gauss-Newton normal equations of a fit whose frames share the shape: K shape columns, then B
// columns per frame (pose, translation, scale). A frame's data touch the shape and that frame's own
// columns only, so H is an arrow: a shape block, a shape-by-frame band, and one block per frame on
// the diagonal. Stored as those blocks and solved through the Schur complement on the shape, the
// cost grows linearly with the frames (O(F (B^3 + K B^2) + K^3)) where a dense system of
// K + F B columns grew with their cube (70 frames: 29 minutes and 1.3 GB).
#pragma once

#include "common/thread_pool.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace ssc::fitting {

class ArrowSystem {
public:
    // Zero blocks for K shape columns and F frames of B columns each.
    void reset(uint32_t K, uint32_t B, uint32_t F);

    uint32_t shape_columns() const { return K_; }
    uint32_t frame_columns() const { return B_; }
    uint32_t frames() const { return F_; }
    uint32_t columns() const { return K_ + F_ * B_; }

    // Adds v to H(r, c), r <= c (global columns: shape 0..K-1, frame f's K + f B ...). The pair
    // must lie in the arrow: both in frame f's columns, or one a shape column.
    void add(uint32_t r, uint32_t c, double v) {
        if (c < K_) shape_(r, c) += v;
        else if (r < K_) band_[(c - K_) / B_](r, (c - K_) % B_) += v;
        else frame_[(r - K_) / B_]((r - K_) % B_, (c - K_) % B_) += v;
    }
    // H(r, c) for r <= c (0 outside the arrow).
    double at(uint32_t r, uint32_t c) const;

    // The blocks: shape (K x K, upper triangle), per frame the band (K x B, shape rows) and the
    // frame's own block (B x B, upper triangle).
    Eigen::MatrixXd& shape_block() { return shape_; }
    Eigen::MatrixXd& band(uint32_t f) { return band_[f]; }
    Eigen::MatrixXd& frame_block(uint32_t f) { return frame_[f]; }

    // Solves (H + mu D) d = -g for the given columns (sorted, global; the others stay 0), where D
    // is H's diagonal (at least 1e-9) and 1e-12 is added to keep it definite: the damped
    // Levenberg-Marquardt step. Frames are eliminated on the pool's threads; their sums enter in
    // frame order, so the result does not depend on the thread count.
    Eigen::VectorXd damped_solve(const Eigen::VectorXd& g, const std::vector<int>& cols, double mu, ThreadPool& pool) const;

private:
    uint32_t K_ = 0, B_ = 0, F_ = 0;
    Eigen::MatrixXd shape_;
    std::vector<Eigen::MatrixXd> band_, frame_;
};

}  // namespace ssc::fitting
