// The fit's priors (energy terms that do not depend on the data): the Gaussian shape prior, each
// joint's rotation prior and the soft walls at the anatomical joint limits.
#pragma once

#include "fitting/arrow_system.hpp"
#include "fitting/kinematics.hpp"

#include <Eigen/Core>

#include <vector>

namespace ssc::fitting {

// Joint limits are soft walls: beyond a limit the cost grows as (excess / kLimitSigma)^2 / 2, so
// 10 degrees past a limit costs as much as 75 scan points each 3 sigma off.
constexpr double kLimitSigma = 0.02;

// The rotation vector of a unit quaternion (radians times axis).
Vector3d log_rotation(const Eigen::Quaterniond& q);

// The pose prior and the limit walls of one frame. Built once per fit from the model: each joint's
// sigma from its role (LinearModel::roles, anatomy/joint_roles.hpp), the fingers' closed rotations
// (anatomy/hand_closure.hpp), the joint limits (LinearModel::limits). Immutable once built.
class PosePrior {
public:
    // weight multiplies the rotation prior (FitOptions::pose_prior); limits: whether the walls apply.
    PosePrior(const LinearModel& lin, double weight, bool limits);

    // Cost of a frame's pose (kin updated to `state`); with H and g, adds its Gauss-Newton normal
    // equations: the frame's columns are the kinematics' own offsets plus frame_offset (frame f of
    // a fit of several: f times the per-frame parameters, as the shape's columns come first and
    // are shared).
    double evaluate(const Kinematics& kin, const FitState& state, uint32_t frame_offset, ArrowSystem* H, Eigen::VectorXd* g) const;

    // Whether the coarse stages move joint j (anatomy/joint_roles.hpp).
    bool coarse(uint32_t j) const { return coarse_joint_[j] != 0; }

private:
    double weight_;
    std::vector<double> joint_sigma_;       // per joint: the rotation prior's sigma
    std::vector<uint8_t> coarse_joint_;     // per joint: moved by the coarse stages
    std::vector<Vector3d> closed_fingers_;  // per joint: a finger's rotation vector at closure 1, else zero
    std::vector<int8_t> hand_of_joint_;     // per joint: 0 left hand's finger, 1 right, -1 neither
    std::vector<anatomy::JointLimit> limits_;  // empty when the walls are off
};

// The shape prior: the coefficients are standard deviations of the training population, so the
// prior is 0.5 weight |shape|^2, added into cost term by term. With H and g, adds its normal
// equations (shape columns first).
// Components from whole_body on (a LinearModel's segments) weigh segment_weight times more.
void add_shape_prior(const std::vector<double>& shape, double weight, uint32_t whole_body, double segment_weight, double& cost,
                     ArrowSystem* H, Eigen::VectorXd* g);

}  // namespace ssc::fitting
