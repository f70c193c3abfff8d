// Naming a direction by the nearest signed axis, as scans' up axes are named (common/rigid.hpp's
// up_axis_rotation takes the same names).
#pragma once

#include <Eigen/Core>

#include <string>

namespace ssc {

// "x", "-x", "y", "-y", "z" or "-z": the signed axis nearest the direction.
inline std::string nearest_axis_name(const Eigen::Vector3d& direction) {
    int a = 0;
    direction.cwiseAbs().maxCoeff(&a);
    return std::string(direction[a] < 0 ? "-" : "") + "xyz"[a];
}

}  // namespace ssc
