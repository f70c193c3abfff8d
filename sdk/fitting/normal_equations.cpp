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

void NormalEquations::add_to_upper(Eigen::MatrixXd& H) {
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    for (std::size_t b = 0; b < used_; ++b) {
        const Bucket& bk = buckets_[b];
        const auto n = Eigen::Index(bk.cols.size());
        if (n == 0 || bk.rows.empty()) continue;
        const Eigen::Map<const RowMajor> R(bk.rows.data(), Eigen::Index(bk.rows.size()) / n, n);
        product_.resize(n, n);
        product_.setZero();
        product_.selfadjointView<Eigen::Upper>().rankUpdate(R.transpose());
        // cols is sorted, so the upper triangle of the block lands in H's upper triangle.
        for (Eigen::Index c = 0; c < n; ++c)
            for (Eigen::Index r = 0; r <= c; ++r) H(bk.cols[std::size_t(r)], bk.cols[std::size_t(c)]) += product_(r, c);
    }
}

}  // namespace ssc::fitting
