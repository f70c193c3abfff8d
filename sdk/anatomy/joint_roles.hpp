// What each joint is to the fitter and the trainer: the body part it moves, its side, how freely
// a fit may turn it, whether the fit's coarse stage moves it, and which joint of an arm or leg the
// limb search poses.
//
// Roles are model data (the file's optional joint_roles, written by training). A model without
// them gets this file's table, the one place where rules are keyed by joint names (the game-engine
// rig's: pelvis, spine_01, upperarm_l, index_01_r, ...); unknown names get torso, loose, moved by
// the coarse stage, no limb.
#pragma once

#include "synthesis/model.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace ssc::anatomy {

// The parts also name the model's vertex sets (training writes one per part). The values are the
// file's.
enum class BodyPart : uint8_t { Torso = 0, Head = 1, Arm = 2, Hand = 3, Leg = 4, Foot = 5 };
enum class Side : uint8_t { Centre = 0, Left = 1, Right = 2 };
// Of an arm or leg, the joints the limb search poses together: the upper (shoulder, hip) and the
// middle (elbow, knee), everything below following.
enum class LimbJoint : uint8_t { None = 0, Upper = 1, Middle = 2 };

struct JointRole {
    BodyPart part = BodyPart::Torso;
    Side side = Side::Centre;
    // Standard deviation (radians) of the fit's prior on the joint's rotation: loose for the trunk
    // and limbs, tighter for the wrists (a flat hand fits nearly as well turned over), tight for the
    // fingers and toes, which sparse data rarely constrain.
    double rotation_sigma = 0.6;
    // Moved by the fit's coarse stage: the trunk and limbs, not the wrists, fingers or toes, whose
    // far-reaching coarse correspondences bent a hand over a hole in a scan onto the forearm.
    bool coarse = true;
    LimbJoint limb_joint = LimbJoint::None;
};

// The table's roles for a skeleton's joint names, as the file stores them (training writes these).
std::vector<format::JointRole> compute_joint_roles(const format::Skeleton& skeleton);

// One role per joint of the model: the file's, else the table's for its names.
std::vector<JointRole> joint_roles(const Model& model);

// The joint of a limb (part Arm or Leg, side Left or Right) that has the given limb role, or -1.
int64_t find_limb_joint(const std::vector<JointRole>& roles, BodyPart part, Side side, LimbJoint which);

// "head", "torso", "arms", "hands", "legs", "feet": the vertex set names.
const char* part_name(BodyPart part);

}  // namespace ssc::anatomy
