#include "registration/rbf_warp.hpp"

#include "common/error.hpp"

#include <Eigen/LU>
#include <Eigen/QR>

#include <cmath>

namespace ssc::registration {

RbfWarp::RbfWarp(std::vector<Eigen::Vector3d> from, const std::vector<Eigen::Vector3d>& to, RbfKernel kernel, double scale)
    : from_(std::move(from)), kernel_(kernel), scale_(scale) {
    const std::size_t L = from_.size();
    SSC_REQUIRE_ARG(L >= 4 && to.size() == L, "rbf warp: at least 4 corresponding landmarks");
    SSC_REQUIRE_ARG(std::isfinite(scale) && scale > 0, "rbf warp: the kernel scale must be positive");
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(Eigen::Index(L + 4), Eigen::Index(L + 4));
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(Eigen::Index(L + 4), 3);
    for (std::size_t i = 0; i < L; ++i) {
        for (std::size_t j = 0; j < L; ++j) M(Eigen::Index(i), Eigen::Index(j)) = phi((from_[i] - from_[j]).norm());
        for (int a = 0; a < 3; ++a) {
            M(Eigen::Index(i), Eigen::Index(L) + a) = M(Eigen::Index(L) + a, Eigen::Index(i)) = from_[i][a];
            rhs(Eigen::Index(i), a) = to[i][a];
        }
        M(Eigen::Index(i), Eigen::Index(L + 3)) = M(Eigen::Index(L + 3), Eigen::Index(i)) = 1;
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(M);
    SSC_REQUIRE_ARG(lu.isInvertible(), "rbf warp: the landmarks are degenerate (repeated, or all in one plane)");
    coefficients_ = lu.solve(rhs);
    SSC_REQUIRE_ARG(coefficients_.allFinite(), "rbf warp: the landmarks are degenerate");
}

double RbfWarp::phi(double r) const {
    switch (kernel_) {
        case RbfKernel::ThinPlate: return r > 0 ? r * r * std::log(r) : 0.0;
        case RbfKernel::Multiquadric: return std::sqrt(r * r + scale_ * scale_);
        case RbfKernel::Gaussian: return std::exp(-r * r / (scale_ * scale_));
    }
    return 0;
}

Eigen::Vector3d RbfWarp::operator()(const Eigen::Vector3d& x) const {
    const Eigen::Index L = Eigen::Index(from_.size());
    Eigen::Vector3d y = coefficients_.row(L + 3).transpose();
    for (int a = 0; a < 3; ++a) y += x[a] * coefficients_.row(L + a).transpose();
    for (Eigen::Index l = 0; l < L; ++l) y += phi((x - from_[std::size_t(l)]).norm()) * coefficients_.row(l).transpose();
    return y;
}

}  // namespace ssc::registration
