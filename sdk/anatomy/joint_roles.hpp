// What each joint is to the fitter and the trainer: the body part it moves, how freely the fit may
// turn it, and whether the coarse stage moves it. The one place where rules are keyed by joint
// names (the game-engine rig's: pelvis, spine_01, upperarm_l, index_01_r, ...); a model learned
// with another skeleton gets the roles this table gives its names (unknown names: torso, free).
#pragma once

#include <string>

namespace ssc::anatomy {

// The parts also name the model's vertex sets (training writes one per part).
enum class BodyPart { Head, Torso, Arm, Hand, Leg, Foot };

struct JointRole {
    BodyPart part;
    // Standard deviation (radians) of the fit's prior on the joint's rotation: loose for the trunk
    // and limbs, tighter for the wrists (a flat hand fits nearly as well turned over), tight for the
    // fingers and toes, which sparse data rarely constrain.
    double rotation_sigma;
    // Moved by the fit's coarse stage: the trunk and limbs, not the wrists, fingers or toes, whose
    // far-reaching coarse correspondences bent a hand over a hole in a scan onto the forearm.
    bool coarse;
};

JointRole joint_role(const std::string& joint_name);

// "head", "torso", "arms", "hands", "legs", "feet": the vertex set names.
const char* part_name(BodyPart part);

}  // namespace ssc::anatomy
