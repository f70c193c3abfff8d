// Named poses (T-pose, A-pose, sitting, arms raised): each defined by anatomical joint angles in
// the frames of joint_limits.hpp, so one definition serves both sides and any model whose rig has
// the game-engine joint names. Every angle lies within the joint's anatomical limits.
#pragma once

#include "anatomy/joint_limits.hpp"
#include "synthesis/model.hpp"

#include <string>
#include <vector>

namespace ssc::anatomy {

struct NamedPose {
    const char* name;         // snake_case, stable: the C API and `sscape synth --pose` use it
    const char* description;
};

// Every named pose, in the order of the C API's indices.
const std::vector<NamedPose>& named_poses();

// The local joint rotations of a named pose for a model: 4 floats (x y z w) per joint, identity for
// joints the pose leaves alone or the rig lacks. Throws ssc::Error(SSC_ERROR_NOT_FOUND) for an
// unknown name. limits: the model's joint_limits() where the caller holds them (the C API's
// model, the fitter's LinearModel); null: made for this call.
std::vector<float> named_pose(const Model& model, const std::string& name, const std::vector<JointLimit>* limits = nullptr);

}  // namespace ssc::anatomy
