#include "semantics/attribute_model.hpp"

#include "common/error.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cstdio>

namespace ssc::semantics {

AttributeModel::AttributeModel(const format::ModelData& d) : K_(d.component_count()) {
    const auto& am = d.attributes;
    attributes_ = am.attributes;
    const Eigen::Index A = Eigen::Index(attributes_.size());
    covariance_.resize(A, A);
    shape_covariance_.resize(A, K_);
    for (Eigen::Index a = 0; a < A; ++a) {
        for (Eigen::Index b = 0; b < A; ++b) covariance_(a, b) = am.covariance[std::size_t(a * A + b)];
        for (uint32_t k = 0; k < K_; ++k) shape_covariance_(a, k) = am.shape_covariance[std::size_t(a) * K_ + k];
        if (attributes_[std::size_t(a)].slider) sliders_.push_back(int(a));
    }
    const Eigen::Index S = Eigen::Index(sliders_.size());
    slider_means_.resize(S);
    Eigen::MatrixXd css(S, S), ccs(K_, S);
    for (Eigen::Index i = 0; i < S; ++i) {
        slider_means_(i) = attributes_[std::size_t(sliders_[std::size_t(i)])].mean;
        for (Eigen::Index j = 0; j < S; ++j) css(i, j) = covariance_(sliders_[std::size_t(i)], sliders_[std::size_t(j)]);
        ccs.col(i) = shape_covariance_.row(sliders_[std::size_t(i)]).transpose();
    }
    if (S == 0) return;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(css);
    SSC_REQUIRE_MODEL(ldlt.info() == Eigen::Success && ldlt.isPositive() && ldlt.vectorD().minCoeff() > 1e-12 * css.diagonal().maxCoeff(),
                      "the sliders' covariance is singular");
    directions_ = ldlt.solve(ccs.transpose()).transpose();  // C_cS C_SS^-1 (C_SS symmetric)
    const Eigen::MatrixXd dtd = directions_.transpose() * directions_;
    const Eigen::LDLT<Eigen::MatrixXd> normal(dtd);
    SSC_REQUIRE_MODEL(normal.info() == Eigen::Success && normal.vectorD().minCoeff() > 1e-12 * dtd.diagonal().maxCoeff(),
                      "the slider directions are linearly dependent");
    readback_ = normal.solve(directions_.transpose());
}

int AttributeModel::find(const std::string& name) const {
    for (std::size_t a = 0; a < attributes_.size(); ++a)
        if (attributes_[a].name == name) return int(a);
    return -1;
}

std::pair<double, double> AttributeModel::accepted_range(int attribute) const {
    const auto& a = attributes_.at(std::size_t(attribute));
    const double width = double(a.maximum) - double(a.minimum);
    double lo = double(a.minimum) - width;
    if (!a.unit.empty()) lo = std::max(lo, 0.0);
    return {lo, double(a.maximum) + width};
}

void AttributeModel::check_accepted(int attribute, double value) const {
    const auto [lo, hi] = accepted_range(attribute);
    if (value >= lo && value <= hi) return;  // false for NaN
    const auto& a = attributes_[std::size_t(attribute)];
    char text[160];
    std::snprintf(text, sizeof text, "%s %g%s%s is outside the accepted range %g to %g%s%s (the population spans %g to %g)",
                  a.name.c_str(), value, a.unit.empty() ? "" : " ", a.unit.c_str(), lo, hi, a.unit.empty() ? "" : " ",
                  a.unit.c_str(), double(a.minimum), double(a.maximum));
    fail(SSC_ERROR_INVALID_ARGUMENT, text);
}

Eigen::VectorXd AttributeModel::conditional_shape(const std::vector<std::pair<int, double>>& known) const {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(K_);
    if (known.empty() || attributes_.empty()) return c;
    const Eigen::Index O = Eigen::Index(known.size());
    Eigen::MatrixXd coo(O, O), coc(O, K_);
    Eigen::VectorXd dev(O);
    for (Eigen::Index i = 0; i < O; ++i) {
        const int a = known[std::size_t(i)].first;
        dev(i) = known[std::size_t(i)].second - attributes_[std::size_t(a)].mean;
        coc.row(i) = shape_covariance_.row(a);
        for (Eigen::Index j = 0; j < O; ++j) coo(i, j) = covariance_(a, known[std::size_t(j)].first);
    }
    // A relative ridge keeps nearly collinear attributes (chest and underbust, stature and inseam)
    // from amplifying small inconsistencies in a request.
    coo.diagonal() *= 1.0 + 1e-3;
    return coc.transpose() * coo.ldlt().solve(dev);
}

Eigen::VectorXd AttributeModel::sliders_to_shape(const Eigen::VectorXd& values) const {
    if (sliders_.empty()) return Eigen::VectorXd::Zero(K_);
    return directions_ * (values - slider_means_);
}

Eigen::VectorXd AttributeModel::shape_to_sliders(const Eigen::VectorXd& coefficients) const {
    if (sliders_.empty()) return Eigen::VectorXd();
    return slider_means_ + readback_ * coefficients;
}

}  // namespace ssc::semantics
