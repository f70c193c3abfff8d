// Least-squares similarity alignment of corresponding point sets (Umeyama 1991; Kabsch without
// scale): dst ~ scale * R * src + t, R a proper rotation.
#pragma once

#include <Eigen/Core>

#include <string>

namespace ssc {

struct Similarity {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    double scale = 1;
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
};

// src and dst: one point per column, same count (>= 3 for a unique answer). with_scale false
// fixes the scale at 1 (rigid).
Similarity align_points(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst, bool with_scale);

// The rotation taking a scan's named up axis ("x", "y", "z", "-x", "-y", "-z"; empty: "y") to +Y,
// the model's up. Anything else is treated as "y"; callers validate the name.
Eigen::Matrix3d up_axis_rotation(const std::string& up);

}  // namespace ssc
