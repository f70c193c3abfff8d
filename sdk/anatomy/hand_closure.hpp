// How a hand closes: one number per hand, 0 the model's open rest hand, 1 a loose fist. Scanned
// people hold their hands relaxed or closed while the model's are spread open, so the fitter
// searches this closure per hand (fitting/hand_search.hpp) and the simulator poses hands with it.
//
// Each finger segment flexes towards the palm about the axis across it: the segment's bone
// direction crossed with the palm normal, the normal from the knuckles' rest positions (hand to
// index_01 and to pinky_01; the side fixes its sign). So any model whose rig has the game-engine
// hand joints closes its hands, whatever its bone frames. Angles at full closure, after the
// finger joints' ranges (MCP about 90, PIP about 100-110, DIP about 80 degrees of flexion):
// knuckles 80, middle joints 95, end joints 65; the thumb folds less (15, 30, 40) and across the
// palm.
#pragma once

#include "synthesis/model.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace ssc::anatomy {

using Eigen::Vector3d;

struct JointRotation {
    uint32_t joint;
    Eigen::Quaterniond rotation;  // local, in the joint's rest frame (as FitState::pose)
};

// The local rotations of one hand's finger joints closed by `closure` (clamped to [0, 1]); side 'l'
// or 'r'. Empty when the rig lacks the hand, index_01 or pinky_01 joint.
std::vector<JointRotation> hand_closure(const Model& model, char side, double closure);

}  // namespace ssc::anatomy
