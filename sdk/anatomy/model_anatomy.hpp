// A model's anatomical data, derived once from its file and shared read-only by everything that
// poses or fits it (the C API's model, the fitter): the joint limits and the joint roles.
#pragma once

#include "anatomy/joint_limits.hpp"
#include "anatomy/joint_roles.hpp"

#include <memory>
#include <vector>

namespace ssc::anatomy {

struct ModelAnatomy {
    explicit ModelAnatomy(const Model& model) : limits(joint_limits(model)), roles(joint_roles(model)) {}
    std::vector<JointLimit> limits;  // per joint (joint_limits.hpp)
    std::vector<JointRole> roles;    // per joint (joint_roles.hpp)
};

}  // namespace ssc::anatomy
