#include "fitting/normal_equations.hpp"

namespace ssc::fitting {

std::size_t NormalEquations::Hash::operator()(const std::vector<uint32_t>& v) const {
    std::size_t h = v.size();
    for (uint32_t c : v) h = h * 1000003u ^ c;
    return h;
}

void NormalEquations::clear() {
    sets_.clear();
    index_.clear();
}

void NormalEquations::reset() {
    for (Set& s : sets_) s.reserved = 0;
}

uint32_t NormalEquations::column_set(const std::vector<uint32_t>& cols) {
    auto [it, inserted] = index_.try_emplace(cols, uint32_t(sets_.size()));
    if (inserted) sets_.emplace_back().cols = cols;
    return it->second;
}

std::size_t NormalEquations::reserve(uint32_t set, uint32_t rows) {
    const std::size_t first = sets_[set].reserved;
    sets_[set].reserved += rows;
    return first;
}

void NormalEquations::allocate() {
    for (Set& s : sets_) s.rows.resize(s.reserved * s.cols.size());
}

void NormalEquations::add_to_upper(Eigen::MatrixXd& H, ThreadPool& pool) {
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    pool.parallel_for(sets_.size(), [&](std::size_t b, unsigned) {
        Set& s = sets_[b];
        if (s.reserved == 0) return;
        const auto n = Eigen::Index(s.cols.size());
        // rankUpdate adds to the upper triangle only, and only that is read: the rest stays as is.
        s.product.resize(n, n);
        s.product.triangularView<Eigen::Upper>().setZero();
        const Eigen::Map<const RowMajor> R(s.rows.data(), Eigen::Index(s.reserved), n);
        s.product.selfadjointView<Eigen::Upper>().rankUpdate(R.transpose());
    });
    for (const Set& s : sets_) {
        if (s.reserved == 0) continue;
        // cols is sorted, so the upper triangle of the block lands in H's upper triangle.
        for (Eigen::Index c = 0; c < s.product.cols(); ++c)
            for (Eigen::Index r = 0; r <= c; ++r) H(s.cols[std::size_t(r)], s.cols[std::size_t(c)]) += s.product(r, c);
    }
}

}  // namespace ssc::fitting
