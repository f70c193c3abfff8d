// Which way a fitted body stands and faces in the frame it was fitted in.
#pragma once

#include "fitting/kinematics.hpp"

#include <Eigen/Geometry>

namespace ssc::fitting {

// The fitted body's orientation in the fit's frame: the root's pose rotation acting in its rest
// frame (R0 P R0^T); its columns are where the model's +X, +Y (up) and +Z (forward) went.
inline Eigen::Matrix3d fitted_body_orientation(const format::ModelData& model, const FitState& fit) {
    if (fit.pose.empty()) return Eigen::Matrix3d::Identity();
    const float* r0 = model.skeleton.rest_orientations.data();
    const Eigen::Matrix3d R0 = Eigen::Quaterniond(r0[3], r0[0], r0[1], r0[2]).normalized().toRotationMatrix();
    return R0 * fit.pose[0].normalized().toRotationMatrix() * R0.transpose();
}

}  // namespace ssc::fitting
