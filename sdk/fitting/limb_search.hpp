// The fitter's search over arm and leg poses, between its coarse and fine stages.
//
// Why: the coarse stage's correspondences reach 10 cm, so from the rest pose an arm raised above
// the head stays fitted to the torso, and a leg stepping far forward stays straight. For each arm
// and leg, a grid of anatomical poses of its upper joint (raised sideways and forwards, along the
// body, turned) times bends of its middle joint (elbow, knee) is scored together, because which
// way a bent elbow points depends on both. The score is the explained() measure of explained.hpp
// (LimbScore: only the limb re-posed); the current pose is a candidate too. The best six of those
// scoring within 1.5 times the current pose are refined by pattern search within the joint limits
// (16 degree steps), the best two further (8 and 4 degrees). A refinement step scores a neighbour
// only until it cannot beat the current pose, and takes poses it has scored before from a memo (a
// fifth of the steps on the benchmark's scans): the same choices for less scoring.
#pragma once

#include "common/thread_pool.hpp"
#include "fitting/explained.hpp"
#include "fitting/kinematics.hpp"
#include "synthesis/body.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ssc::fitting {

// The limbs searched, in their order: left arm, right arm, left leg, right leg.
constexpr std::size_t kLimbCount = 4;
// Per limb, the relative gain of the measure, 1 - best / current, when it moved (else 0).
using LimbGains = std::array<double, kLimbCount>;

// Searches the first `count` limbs of one frame (kLimbCount: all), one after another, and moves
// each to its best pose. kin and body: scratch for the frame's model (their state is overwritten).
// state: the frame's state, updated. cloud: the frame's cloud; vertex_sample: area-uniform model
// vertices. Candidates are scored on the pool's threads; the result does not depend on their
// number. Models without joint limits or without the limbs' joints (LinearModel::roles: each limb's upper
// and middle joint) are left as they are (gain 0).
LimbGains search_limbs(Kinematics& kin, Body& body, FitState& state, const CloudView& cloud, const std::vector<uint32_t>& vertex_sample,
                       ThreadPool& pool, std::size_t count = kLimbCount);

}  // namespace ssc::fitting
