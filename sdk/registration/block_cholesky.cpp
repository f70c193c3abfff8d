#include "registration/block_cholesky.hpp"

#include "common/error.hpp"

#include <Eigen/Cholesky>
#include <Eigen/OrderingMethods>

#include <algorithm>

namespace ssc::registration {

void BlockCholesky4::analyze(const Eigen::SparseMatrix<double>& K) {
    SSC_REQUIRE_ARG(K.rows() == K.cols() && K.rows() % 4 == 0 && K.isCompressed(), "block Cholesky: a compressed 4n x 4n matrix");
    n_ = uint32_t(K.rows() / 4);
    // The block graph, ordered by approximate minimum degree.
    std::vector<Eigen::Triplet<double>> t;
    for (Eigen::Index c = 0; c < K.cols(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it) t.emplace_back(int(it.row() / 4), int(c / 4), 1.0);
    Eigen::SparseMatrix<double> G(n_, n_);
    G.setFromTriplets(t.begin(), t.end());
    G.makeCompressed();
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;
    Eigen::AMDOrdering<int>()(G, order);  // order.indices()[new] = old
    old_of_new_.assign(order.indices().data(), order.indices().data() + n_);
    new_of_old_.assign(n_, 0);
    for (uint32_t k = 0; k < n_; ++k) new_of_old_[old_of_new_[k]] = k;
    // The upper triangle's blocks by new column, each column's rows sorted.
    std::vector<std::vector<uint32_t>> rows(n_);
    for (Eigen::Index c = 0; c < G.cols(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(G, c); it; ++it) {
            const uint32_t i = new_of_old_[std::size_t(it.row())], j = new_of_old_[std::size_t(c)];
            if (i <= j) rows[j].push_back(i);
        }
    upper_ptr_.assign(n_ + 1, 0);
    upper_row_.clear();
    for (uint32_t j = 0; j < n_; ++j) {
        std::sort(rows[j].begin(), rows[j].end());
        SSC_REQUIRE_ARG(!rows[j].empty() && rows[j].back() == j, "block Cholesky: every diagonal block must be present");
        upper_row_.insert(upper_row_.end(), rows[j].begin(), rows[j].end());
        upper_ptr_[j + 1] = upper_row_.size();
    }
    upper_.assign(upper_row_.size(), Block::Zero());
    // Where each stored entry of K goes: entries of the upper triangle (in the new order) only.
    destination_.assign(std::size_t(K.nonZeros()), -1);
    for (Eigen::Index c = 0; c < K.cols(); ++c)
        for (Eigen::Index p = K.outerIndexPtr()[c]; p < K.outerIndexPtr()[c + 1]; ++p) {
            const Eigen::Index r = K.innerIndexPtr()[p];
            const uint32_t i = new_of_old_[std::size_t(r / 4)], j = new_of_old_[std::size_t(c / 4)];
            if (i > j) continue;
            const auto begin = upper_row_.begin() + std::ptrdiff_t(upper_ptr_[j]), end = upper_row_.begin() + std::ptrdiff_t(upper_ptr_[j + 1]);
            const std::size_t slot = std::size_t(std::lower_bound(begin, end, i) - upper_row_.begin());
            destination_[std::size_t(p)] = int64_t(16 * slot + std::size_t(r % 4) + 4 * std::size_t(c % 4));  // column-major 4x4
        }
    // The elimination tree (cs_etree, with path compression).
    parent_.assign(n_, -1);
    std::vector<int32_t> ancestor(n_, -1);
    for (uint32_t k = 0; k < n_; ++k)
        for (std::size_t p = upper_ptr_[k]; p < upper_ptr_[k + 1]; ++p) {
            for (int32_t i = int32_t(upper_row_[p]); i != -1 && i < int32_t(k);) {
                const int32_t next = ancestor[std::size_t(i)];
                ancestor[std::size_t(i)] = int32_t(k);
                if (next == -1) parent_[std::size_t(i)] = int32_t(k);
                i = next;
            }
        }
    // The factor's column counts: each row k's pattern (the reach of its upper column in the
    // tree) adds one block to each column it names.
    std::vector<std::size_t> count(n_, 0);
    std::vector<uint32_t> mark(n_, UINT32_MAX);
    for (uint32_t k = 0; k < n_; ++k) {
        mark[k] = k;
        for (std::size_t p = upper_ptr_[k]; p < upper_ptr_[k + 1]; ++p)
            for (int32_t i = int32_t(upper_row_[p]); i != -1 && mark[std::size_t(i)] != k; i = parent_[std::size_t(i)]) {
                mark[std::size_t(i)] = k;
                ++count[std::size_t(i)];
            }
    }
    l_ptr_.assign(n_ + 1, 0);
    for (uint32_t j = 0; j < n_; ++j) l_ptr_[j + 1] = l_ptr_[j] + count[j];
    l_row_.assign(l_ptr_[n_], 0);
    l_value_.assign(l_ptr_[n_], Block::Zero());
    diagonal_.assign(n_, Block::Identity());
}

bool BlockCholesky4::factorize(const Eigen::SparseMatrix<double>& K) {
    SSC_REQUIRE_ARG(std::size_t(K.nonZeros()) == destination_.size() && K.rows() == Eigen::Index(4 * n_),
                    "block Cholesky: the matrix does not have the analysed structure");
    for (Block& b : upper_) b.setZero();
    double* up = upper_.data()->data();
    const double* value = K.valuePtr();
    for (std::size_t p = 0; p < destination_.size(); ++p)
        if (destination_[p] >= 0) up[destination_[p]] = value[p];
    // Up-looking: row k of L from a sparse triangular solve against the rows above it.
    std::vector<Block, Eigen::aligned_allocator<Block>> x(n_, Block::Zero());
    std::vector<std::size_t> fill(l_ptr_.begin(), l_ptr_.end() - 1);  // next free slot per column
    std::vector<uint32_t> mark(n_, UINT32_MAX), stack(n_), path(n_);
    for (uint32_t k = 0; k < n_; ++k) {
        // The pattern of row k (ereach): the rows reached from its upper column, in topological order.
        std::size_t top = n_;
        mark[k] = k;
        for (std::size_t p = upper_ptr_[k]; p < upper_ptr_[k + 1]; ++p) {
            uint32_t i = upper_row_[p];
            x[i] = upper_[p];  // scatter K(i, k)
            std::size_t len = 0;
            for (; mark[i] != k; i = uint32_t(parent_[i])) {
                path[len++] = i;
                mark[i] = k;
            }
            while (len > 0) stack[--top] = path[--len];
        }
        Block d = x[k];
        x[k].setZero();
        for (std::size_t s = top; s < n_; ++s) {
            const uint32_t i = stack[s];
            // L(i, i) L(k, i)^T = x_i  ->  Y = L(k, i)^T
            const Block Y = diagonal_[i].triangularView<Eigen::Lower>().solve(x[i]);
            x[i].setZero();
            for (std::size_t p = l_ptr_[i]; p < fill[i]; ++p) x[l_row_[p]].noalias() -= l_value_[p] * Y;
            d.noalias() -= Y.transpose() * Y;
            l_row_[fill[i]] = k;
            l_value_[fill[i]++] = Y.transpose();
        }
        const Eigen::LLT<Block> llt(d);
        if (llt.info() != Eigen::Success) return false;
        diagonal_[k] = llt.matrixL();
    }
    return true;
}

Eigen::MatrixX3d BlockCholesky4::solve(const Eigen::MatrixX3d& B) const {
    SSC_REQUIRE_ARG(B.rows() == Eigen::Index(4 * n_), "block Cholesky: the right-hand side needs 4n rows");
    using Rhs = Eigen::Matrix<double, 4, 3>;
    std::vector<Rhs, Eigen::aligned_allocator<Rhs>> y(n_);
    for (uint32_t k = 0; k < n_; ++k) y[k] = B.block<4, 3>(4 * Eigen::Index(old_of_new_[k]), 0);
    for (uint32_t j = 0; j < n_; ++j) {  // L y = b
        y[j] = diagonal_[j].triangularView<Eigen::Lower>().solve(y[j]);
        for (std::size_t p = l_ptr_[j]; p < l_ptr_[j + 1]; ++p) y[l_row_[p]].noalias() -= l_value_[p] * y[j];
    }
    for (uint32_t j = n_; j-- > 0;) {  // L^T x = y
        for (std::size_t p = l_ptr_[j]; p < l_ptr_[j + 1]; ++p) y[j].noalias() -= l_value_[p].transpose() * y[l_row_[p]];
        y[j] = diagonal_[j].transpose().triangularView<Eigen::Upper>().solve(y[j]);
    }
    Eigen::MatrixX3d X(B.rows(), 3);
    for (uint32_t k = 0; k < n_; ++k) X.block<4, 3>(4 * Eigen::Index(old_of_new_[k]), 0) = y[k];
    return X;
}

}  // namespace ssc::registration
