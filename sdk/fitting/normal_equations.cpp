#include "fitting/normal_equations.hpp"

namespace ssc::fitting {

std::size_t NormalEquations::Hash::operator()(const std::vector<uint32_t>& v) const {
    std::size_t h = v.size();
    for (uint32_t c : v) h = h * 1000003u ^ c;
    return h;
}

void NormalEquations::reset() {
    for (std::size_t b = 0; b < used_; ++b) buckets_[b].rows.clear();
    used_ = 0;
    index_.clear();
}

void NormalEquations::add(const std::vector<uint32_t>& cols, const double* J, uint32_t rows) {
    auto [it, inserted] = index_.try_emplace(cols, used_);
    if (inserted) {
        if (used_ == buckets_.size()) buckets_.emplace_back();
        buckets_[used_].cols = cols;
        ++used_;
    }
    auto& rows_of = buckets_[it->second].rows;
    rows_of.insert(rows_of.end(), J, J + std::size_t(rows) * cols.size());
}

void NormalEquations::add_to_upper(Eigen::MatrixXd& H, ThreadPool& pool) {
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    if (products_.size() < used_) products_.resize(used_);
    pool.parallel_for(used_, [&](std::size_t b, unsigned) {
        const Bucket& bk = buckets_[b];
        const auto n = Eigen::Index(bk.cols.size());
        Eigen::MatrixXd& product = products_[b];
        product.resize(n, n);
        product.setZero();
        if (n == 0 || bk.rows.empty()) return;
        const Eigen::Map<const RowMajor> R(bk.rows.data(), Eigen::Index(bk.rows.size()) / n, n);
        product.selfadjointView<Eigen::Upper>().rankUpdate(R.transpose());
    });
    for (std::size_t b = 0; b < used_; ++b) {
        const Bucket& bk = buckets_[b];
        const Eigen::MatrixXd& product = products_[b];
        // cols is sorted, so the upper triangle of the block lands in H's upper triangle.
        for (Eigen::Index c = 0; c < product.cols(); ++c)
            for (Eigen::Index r = 0; r <= c; ++r) H(bk.cols[std::size_t(r)], bk.cols[std::size_t(c)]) += product(r, c);
    }
}

}  // namespace ssc::fitting
