#include "fitting/normal_equations.hpp"

#include <algorithm>
#include <cmath>

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
    // The products go into H on the pool's threads too, each thread a band of H's columns (every
    // set in order, so each entry sums the same terms in the same order for any thread count).
    // Bands are equal shares of the upper triangle: column c holds c + 1 entries.
    constexpr std::size_t kBands = 8;
    const double P = double(H.cols());
    auto band_start = [&](std::size_t b) { return uint32_t(std::lround(P * std::sqrt(double(b) / kBands))); };
    pool.parallel_for(kBands, [&](std::size_t b, unsigned) {
        const uint32_t lo = band_start(b), hi = band_start(b + 1);
        for (const Set& s : sets_) {
            if (s.reserved == 0) continue;
            // cols is sorted, so the upper triangle of the block lands in H's upper triangle.
            const auto first = std::lower_bound(s.cols.begin(), s.cols.end(), lo) - s.cols.begin();
            for (auto c = first; c < Eigen::Index(s.cols.size()) && s.cols[std::size_t(c)] < hi; ++c) {
                double* column = H.col(s.cols[std::size_t(c)]).data();
                for (Eigen::Index r = 0; r <= c; ++r) column[s.cols[std::size_t(r)]] += s.product(r, c);
            }
        }
    });
}

}  // namespace ssc::fitting
