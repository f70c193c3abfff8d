#include "registration/block_cholesky.hpp"

#include "common/error.hpp"

#include <Eigen/Cholesky>
#include <Eigen/OrderingMethods>

#include <algorithm>
#include <functional>

namespace ssc::registration {

namespace {

// The 4x4 block products, written out. Eigen's fixed-size products are the same few multiplies in
// Release, but under the sanitizers they stay calls with poisoned stack temporaries: the
// factorisation there took most of a registration's time, and a registration 7 times its Release
// time. Column-major blocks; C columns on the right (4: the factor, 3: a right-hand side).

// t += sign op(a) b, op(a) = a or its transpose; t is neither a nor b.
template <bool Transpose, int C, int Sign>
inline void add_product(double* __restrict t, const double* __restrict a, const double* __restrict b) {
    for (int c = 0; c < C; ++c)
        for (int k = 0; k < 4; ++k) {
            const double s = Sign * b[4 * c + k];
            for (int r = 0; r < 4; ++r) t[4 * c + r] += (Transpose ? a[4 * r + k] : a[4 * k + r]) * s;
        }
}

template <bool Transpose, int C>
inline void subtract_product(double* t, const double* a, const double* b) {
    add_product<Transpose, C, -1>(t, a, b);
}

// op(a) b as a new block.
template <bool Transpose, int C>
inline Eigen::Matrix<double, 4, C> product(const Eigen::Matrix4d& a, const Eigen::Matrix<double, 4, C>& b) {
    Eigen::Matrix<double, 4, C> t = Eigen::Matrix<double, 4, C>::Zero();
    add_product<Transpose, C, 1>(t.data(), a.data(), b.data());
    return t;
}

}  // namespace

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
    // Each row's work is the block products its factor row takes: column i's blocks so far, for
    // every column i it names.
    std::vector<std::size_t> count(n_, 0);
    std::vector<uint32_t> mark(n_, UINT32_MAX);
    std::vector<double> row_work(n_, 1.0);
    for (uint32_t k = 0; k < n_; ++k) {
        mark[k] = k;
        for (std::size_t p = upper_ptr_[k]; p < upper_ptr_[k + 1]; ++p)
            for (int32_t i = int32_t(upper_row_[p]); i != -1 && mark[std::size_t(i)] != k; i = parent_[std::size_t(i)]) {
                mark[std::size_t(i)] = k;
                row_work[k] += double(++count[std::size_t(i)]);
            }
    }
    l_ptr_.assign(n_ + 1, 0);
    for (uint32_t j = 0; j < n_; ++j) l_ptr_[j + 1] = l_ptr_[j] + count[j];
    l_row_.assign(l_ptr_[n_], 0);
    l_value_.assign(l_ptr_[n_], Block::Zero());
    inverse_diagonal_.assign(n_, Block::Identity());
    split_tree(row_work);
}

// Subtrees are taken from the top of the elimination tree down (the heaviest first) until they
// fall into kParts groups within kBalance of each other, or the top would hold more than
// kMaxTop of the work (then everything is the top: a small or dense matrix gains nothing).
void BlockCholesky4::split_tree(const std::vector<double>& row_work) {
    constexpr std::size_t kParts = 2;
    constexpr double kBalance = 1.1, kMaxTop = 0.5;
    std::vector<double> subtree(row_work);
    std::vector<std::vector<uint32_t>> children(n_);
    std::vector<uint32_t> frontier;
    double total = 0;
    for (uint32_t k = 0; k < n_; ++k) {  // children come before their parents
        total += row_work[k];
        if (parent_[k] < 0) {
            frontier.push_back(k);
        } else {
            subtree[std::size_t(parent_[k])] += subtree[k];
            children[std::size_t(parent_[k])].push_back(k);
        }
    }
    std::vector<uint32_t> top;
    std::vector<std::vector<uint32_t>> bins(kParts);
    double top_work = 0;
    const auto heavier = [&](uint32_t a, uint32_t b) { return subtree[a] > subtree[b] || (subtree[a] == subtree[b] && a < b); };
    bool balanced = false;
    while (!frontier.empty() && top_work <= kMaxTop * total) {
        std::sort(frontier.begin(), frontier.end(), heavier);
        std::vector<double> load(kParts, 0.0);
        for (auto& b : bins) b.clear();
        for (uint32_t r : frontier) {
            const std::size_t lightest = std::size_t(std::min_element(load.begin(), load.end()) - load.begin());
            load[lightest] += subtree[r];
            bins[lightest].push_back(r);
        }
        if (*std::max_element(load.begin(), load.end()) <= kBalance * (total - top_work) / double(kParts)) {
            balanced = true;
            break;
        }
        const uint32_t r = frontier.front();
        frontier.erase(frontier.begin());
        top.push_back(r);
        top_work += row_work[r];
        frontier.insert(frontier.end(), children[r].begin(), children[r].end());
    }
    parts_.clear();
    top_.clear();
    top_slot_.assign(n_, -1);
    if (!balanced || top_work > kMaxTop * total) {
        for (uint32_t k = 0; k < n_; ++k) top_.push_back(k);
    } else {
        for (const auto& bin : bins) {
            std::vector<uint32_t> rows, stack(bin.begin(), bin.end());
            while (!stack.empty()) {
                const uint32_t r = stack.back();
                stack.pop_back();
                rows.push_back(r);
                stack.insert(stack.end(), children[r].begin(), children[r].end());
            }
            std::sort(rows.begin(), rows.end());
            parts_.push_back(std::move(rows));
        }
        top_ = std::move(top);
        std::sort(top_.begin(), top_.end());
    }
    for (std::size_t t = 0; t < top_.size(); ++t) top_slot_[top_[t]] = int32_t(t);
}

void BlockCholesky4::for_each_part(ThreadPool* pool, const std::function<void(std::size_t part)>& fn) const {
    if (pool && pool->size() > 1 && parts_.size() > 1) {
        pool->parallel_for(parts_.size(), [&](std::size_t part, unsigned) { fn(part); });
    } else {
        for (std::size_t part = 0; part < parts_.size(); ++part) fn(part);
    }
}

bool BlockCholesky4::factorize(const Eigen::SparseMatrix<double>& K, ThreadPool* pool) {
    SSC_REQUIRE_ARG(std::size_t(K.nonZeros()) == destination_.size() && K.rows() == Eigen::Index(4 * n_),
                    "block Cholesky: the matrix does not have the analysed structure");
    for (Block& b : upper_) b.setZero();
    double* up = upper_.data()->data();
    const double* value = K.valuePtr();
    for (std::size_t p = 0; p < destination_.size(); ++p)
        if (destination_[p] >= 0) up[destination_[p]] = value[p];
    fill_.assign(l_ptr_.begin(), l_ptr_.end() - 1);
    // One workspace per part (the top uses the first), whichever thread runs it.
    while (workspaces_.size() < std::max<std::size_t>(parts_.size(), 1)) workspaces_.emplace_back(n_);
    std::vector<Workspace>& work = workspaces_;
    for (Workspace& w : work) std::fill(w.mark.begin(), w.mark.end(), UINT32_MAX);  // a row's marks are its index
    std::vector<uint8_t> ok(parts_.size(), 1);
    for_each_part(pool, [&](std::size_t part) {
        for (uint32_t k : parts_[part])
            if (!factor_row(k, work[part])) {
                ok[part] = 0;
                return;
            }
    });
    bool success = std::find(ok.begin(), ok.end(), 0) == ok.end();
    for (std::size_t t = 0; success && t < top_.size(); ++t) success = factor_row(top_[t], work[0]);
    if (!success) workspaces_.clear();  // a failed row leaves its workspace dirty
    return success;
}

// Up-looking: row k of L from a sparse triangular solve against the rows above it.
bool BlockCholesky4::factor_row(uint32_t k, Workspace& w) {
    // The pattern of row k (ereach): the rows reached from its upper column, in topological order.
    std::size_t top = n_;
    w.mark[k] = k;
    for (std::size_t p = upper_ptr_[k]; p < upper_ptr_[k + 1]; ++p) {
        uint32_t i = upper_row_[p];
        w.x[i] = upper_[p];  // scatter K(i, k)
        std::size_t len = 0;
        for (; w.mark[i] != k; i = uint32_t(parent_[i])) {
            w.path[len++] = i;
            w.mark[i] = k;
        }
        while (len > 0) w.stack[--top] = w.path[--len];
    }
    Block d = w.x[k];
    w.x[k].setZero();
    for (std::size_t s = top; s < n_; ++s) {
        const uint32_t i = w.stack[s];
        // L(i, i) L(k, i)^T = x_i  ->  Y = L(k, i)^T
        const Block Y = product<false, 4>(inverse_diagonal_[i], w.x[i]);
        w.x[i].setZero();
        for (std::size_t p = l_ptr_[i]; p < fill_[i]; ++p) subtract_product<false, 4>(w.x[l_row_[p]].data(), l_value_[p].data(), Y.data());
        subtract_product<true, 4>(d.data(), Y.data(), Y.data());
        l_row_[fill_[i]] = k;
        l_value_[fill_[i]++] = Y.transpose();
    }
    const Eigen::LLT<Block> llt(d);
    if (llt.info() != Eigen::Success) return false;
    // Its inverse (lower triangular too) makes each later use a fixed-size product: Eigen's
    // triangular solve took a general path for 4x4 blocks.
    inverse_diagonal_[k] = Block(llt.matrixL()).triangularView<Eigen::Lower>().solve(Block::Identity());
    return true;
}

Eigen::MatrixX3d BlockCholesky4::solve(const Eigen::MatrixX3d& B, ThreadPool* pool) const {
    SSC_REQUIRE_ARG(B.rows() == Eigen::Index(4 * n_), "block Cholesky: the right-hand side needs 4n rows");
    using Rhs = Eigen::Matrix<double, 4, 3>;
    using Rhss = std::vector<Rhs, Eigen::aligned_allocator<Rhs>>;
    Rhss y(n_);
    for (uint32_t k = 0; k < n_; ++k) y[k] = B.block<4, 3>(4 * Eigen::Index(old_of_new_[k]), 0);
    // L y = b: a part's updates of the top's rows are summed apart and added after.
    std::vector<Rhss> top_update(parts_.size(), Rhss(top_.size(), Rhs::Zero()));
    auto forward = [&](uint32_t j, Rhss* to_top) {
        y[j] = product<false, 3>(inverse_diagonal_[j], y[j]);
        for (std::size_t p = l_ptr_[j]; p < l_ptr_[j + 1]; ++p) {
            const uint32_t r = l_row_[p];
            Rhs& target = to_top && top_slot_[r] >= 0 ? (*to_top)[std::size_t(top_slot_[r])] : y[r];
            subtract_product<false, 3>(target.data(), l_value_[p].data(), y[j].data());
        }
    };
    auto backward = [&](uint32_t j) {
        for (std::size_t p = l_ptr_[j]; p < l_ptr_[j + 1]; ++p) subtract_product<true, 3>(y[j].data(), l_value_[p].data(), y[l_row_[p]].data());
        y[j] = product<true, 3>(inverse_diagonal_[j], y[j]);
    };
    for_each_part(pool, [&](std::size_t part) {
        for (uint32_t j : parts_[part]) forward(j, &top_update[part]);
    });
    for (const Rhss& update : top_update)
        for (std::size_t t = 0; t < top_.size(); ++t) y[top_[t]] += update[t];
    for (uint32_t j : top_) forward(j, nullptr);
    // L^T x = y: the top first, then the parts (each reads only its own rows and the top's).
    for (auto it = top_.rbegin(); it != top_.rend(); ++it) backward(*it);
    for_each_part(pool, [&](std::size_t part) {
        for (auto it = parts_[part].rbegin(); it != parts_[part].rend(); ++it) backward(*it);
    });
    Eigen::MatrixX3d X(B.rows(), 3);
    for (uint32_t k = 0; k < n_; ++k) X.block<4, 3>(4 * Eigen::Index(old_of_new_[k]), 0) = y[k];
    return X;
}

}  // namespace ssc::registration
