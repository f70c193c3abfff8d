#include "common/rigid.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>

namespace ssc {

Similarity align_points(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst, bool with_scale) {
    const double n = double(src.cols());
    const Eigen::Vector3d ms = src.rowwise().mean(), md = dst.rowwise().mean();
    const Eigen::Matrix3Xd s = src.colwise() - ms, d = dst.colwise() - md;
    const Eigen::Matrix3d cov = d * s.transpose() / n;
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
    // A reflection in the best orthogonal map is replaced by the nearest rotation.
    Eigen::Vector3d sign(1, 1, (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1);
    Similarity out;
    out.R = svd.matrixU() * sign.asDiagonal() * svd.matrixV().transpose();
    const double var = s.squaredNorm() / n;
    if (with_scale && var > 0) out.scale = svd.singularValues().dot(sign) / var;
    out.t = md - out.scale * out.R * ms;
    return out;
}

Eigen::Matrix3d up_axis_rotation(const std::string& up) {
    Eigen::Vector3d axis = Eigen::Vector3d::UnitY();
    const char a = up.empty() ? 'y' : up.back();
    if (a == 'x') axis = Eigen::Vector3d::UnitX();
    if (a == 'z') axis = Eigen::Vector3d::UnitZ();
    if (!up.empty() && up[0] == '-') axis = -axis;
    return Eigen::Quaterniond::FromTwoVectors(axis, Eigen::Vector3d::UnitY()).toRotationMatrix();
}

}  // namespace ssc
