// A radial-basis-function warp of space through corresponding landmarks: the `rbf` start of a
// registration (the template at rest warped onto the scan's landmarks, as the second S-SCAPE paper's
// rough deformation). f(x) = sum_l w_l phi(|x - s_l|) + A x + b, with f(s_l) = t_l exactly and the
// weights orthogonal to affine functions: one dense linear system of L + 4 rows.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace ssc::registration {

enum class RbfKernel {
    ThinPlate,     // r^2 log r
    Multiquadric,  // sqrt(r^2 + s^2)
    Gaussian,      // exp(-r^2 / s^2)
};

class RbfWarp {
public:
    // from, to: at least 4 corresponding points, not all in one plane; scale: s (metres, > 0) of
    // the multiquadric and Gaussian kernels. Throws ssc::Error (INVALID_ARGUMENT) otherwise or when
    // the system is singular (repeated landmarks).
    RbfWarp(std::vector<Eigen::Vector3d> from, const std::vector<Eigen::Vector3d>& to, RbfKernel kernel, double scale);
    Eigen::Vector3d operator()(const Eigen::Vector3d& x) const;

private:
    double phi(double r) const;
    std::vector<Eigen::Vector3d> from_;
    RbfKernel kernel_;
    double scale_;
    Eigen::MatrixXd coefficients_;  // (L + 4) x 3: the weights, then the affine part (A^T rows, b)
};

}  // namespace ssc::registration
