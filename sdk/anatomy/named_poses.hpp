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

// One joint's anatomical angles in a pose: degrees relative to the rest pose, in the frames of
// joint_limits.hpp (-x' swings the thigh and the upper arm forward and bends the elbow, +x' bends
// the knee and the trunk forward and points the foot down, -z' raises the arm or the thigh
// sideways). A joint without limits (the pelvis, the root of what a pose moves) turns what hangs
// from it: flexion pitches it forward, axial turns it about the up axis, abduction rolls it to its
// right, about the body's axes at rest.
struct JointAngles {
    const char* joint;  // without the side suffix
    double flexion, axial, abduction;
    char side = 'b';    // 'b' both sides, 'l' or 'r' one side, 'm' a midline joint (no suffix)
};

// The local joint rotations (4 floats, x y z w, per joint) of the given angles; joints not named,
// or that the rig lacks, stay at rest; a later entry for the same joint replaces an earlier one.
// Angles are taken as given, not clamped to the limits. limits: as named_pose's.
std::vector<float> pose_from_angles(const Model& model, const std::vector<JointAngles>& angles, const std::vector<JointLimit>* limits = nullptr);

// Every named pose, in the order of the C API's indices.
const std::vector<NamedPose>& named_poses();

// The local joint rotations of a named pose for a model: 4 floats (x y z w) per joint, identity for
// joints the pose leaves alone or the rig lacks. Throws ssc::Error(SSC_ERROR_NOT_FOUND) for an
// unknown name. limits: the model's joint_limits() where the caller holds them (the C API's
// model, the fitter's LinearModel); null: made for this call.
std::vector<float> named_pose(const Model& model, const std::string& name, const std::vector<JointLimit>* limits = nullptr);

}  // namespace ssc::anatomy
