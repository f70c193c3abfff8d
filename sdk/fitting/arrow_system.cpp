#include "fitting/arrow_system.hpp"

#include <Eigen/Cholesky>

namespace ssc::fitting {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// The damped symmetric matrix of the upper triangle `upper`: Cholesky (blocked, no pivoting) is
// the fast path, LDLT only if rounding says the matrix is not definite.
struct Factor {
    Eigen::LLT<MatrixXd> llt;
    Eigen::LDLT<MatrixXd> ldlt;
    bool cholesky = true;
    explicit Factor(MatrixXd a, double mu) {
        for (Eigen::Index i = 0; i < a.rows(); ++i) a(i, i) += mu * std::max(a(i, i), 1e-9) + 1e-12;
        a = a.selfadjointView<Eigen::Upper>();
        llt.compute(a);
        if (llt.info() != Eigen::Success) cholesky = false, ldlt.compute(a);
    }
    template <class M>
    MatrixXd solve(const M& b) const { return cholesky ? MatrixXd(llt.solve(b)) : MatrixXd(ldlt.solve(b)); }
};

}  // namespace

void ArrowSystem::reset(uint32_t K, uint32_t B, uint32_t F) {
    K_ = K, B_ = B, F_ = F;
    shape_.setZero(K, K);
    band_.resize(F);
    frame_.resize(F);
    for (uint32_t f = 0; f < F; ++f) band_[f].setZero(K, B), frame_[f].setZero(B, B);
}

double ArrowSystem::at(uint32_t r, uint32_t c) const {
    if (c < K_) return shape_(r, c);
    if (r < K_) return band_[(c - K_) / B_](r, (c - K_) % B_);
    if ((r - K_) / B_ != (c - K_) / B_) return 0;
    return frame_[(r - K_) / B_]((r - K_) % B_, (c - K_) % B_);
}

VectorXd ArrowSystem::damped_solve(const VectorXd& g, const std::vector<int>& cols, double mu, ThreadPool& pool) const {
    // The columns of each part, as local indices.
    std::vector<int> shape_cols;
    std::vector<std::vector<int>> frame_cols(F_);
    for (int c : cols) {
        const uint32_t u = uint32_t(c);
        if (u < K_) shape_cols.push_back(c);
        else frame_cols[(u - K_) / B_].push_back(int((u - K_) % B_));
    }
    const Eigen::Index ks = Eigen::Index(shape_cols.size());
    auto frame_g = [&](uint32_t f) {
        VectorXd v(Eigen::Index(frame_cols[f].size()));
        for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = g[Eigen::Index(K_ + f * B_) + frame_cols[f][std::size_t(i)]];
        return v;
    };
    // Each frame's elimination: with A its damped block and C its band (shape rows), X = A^-1 C^T
    // and y = A^-1 g_f; the Schur complement loses C X and its right side gains C y.
    struct Eliminated {
        MatrixXd X, CX;
        VectorXd y, Cy;
    };
    std::vector<Eliminated> e(F_);
    pool.parallel_for(F_, [&](std::size_t fi, unsigned) {
        const uint32_t f = uint32_t(fi);
        if (frame_cols[f].empty()) return;
        const Factor A(frame_[f](frame_cols[f], frame_cols[f]), mu);
        e[f].y = A.solve(frame_g(f));
        if (ks == 0) return;  // no shape columns (a rigid stage): nothing couples the frames
        const MatrixXd C = band_[f](shape_cols, frame_cols[f]);
        e[f].X = A.solve(C.transpose());
        e[f].CX = C * e[f].X;
        e[f].Cy = C * e[f].y;
    });
    VectorXd ds = VectorXd::Zero(ks);
    if (ks > 0) {
        MatrixXd S = shape_(shape_cols, shape_cols).selfadjointView<Eigen::Upper>();
        VectorXd rhs = -g(shape_cols);
        for (uint32_t f = 0; f < F_; ++f) {  // in frame order: the same sums for any thread count
            if (frame_cols[f].empty()) continue;
            S -= e[f].CX;
            rhs += e[f].Cy;
        }
        // S is symmetric up to rounding; the factor reads its upper triangle. The shape's damping
        // applies to the shape's own diagonal, before the frames' elimination.
        for (Eigen::Index i = 0; i < ks; ++i) {
            const double d = shape_(shape_cols[std::size_t(i)], shape_cols[std::size_t(i)]);
            S(i, i) += mu * std::max(d, 1e-9) + 1e-12;
        }
        const Factor Sf(S, 0.0);
        ds = Sf.solve(rhs);
    }
    VectorXd delta = VectorXd::Zero(Eigen::Index(columns()));
    for (Eigen::Index i = 0; i < ks; ++i) delta[shape_cols[std::size_t(i)]] = ds[i];
    for (uint32_t f = 0; f < F_; ++f) {
        if (frame_cols[f].empty()) continue;
        const VectorXd df = -e[f].y - (ks > 0 ? VectorXd(e[f].X * ds) : VectorXd::Zero(e[f].y.size()));
        for (Eigen::Index i = 0; i < df.size(); ++i) delta[Eigen::Index(K_ + f * B_) + frame_cols[f][std::size_t(i)]] = df[i];
    }
    return delta;
}

}  // namespace ssc::fitting
