// The fitter's search over how each forearm is turned and each wrist bent, after the fine stage.
//
// Why: a hand is a fifth of the model's vertices and a flat, thin part of the scan: the fine
// stage's short correspondences hold a hand wherever the coarse stages left it, turned over or
// bent the wrong way while it lies on its points (hands 30 to 150 mm off in fits reported
// converged; docs/fitting.md). For each arm: the forearm's turn across its range by three wrist
// bends, then a pattern search over the forearm's turn and the wrist's three anatomical angles,
// scored with the explained measure of forearm and hand (LimbScore of the elbow joint); a pose
// must gain kMinGain (wrist_search.cpp). The solver keeps the result only when the whole fit
// then lies closer to the scan (keep_if_closer in solver.cpp): the measure alone turned good
// hands wrong as often as it fixed bad ones.
#pragma once

#include "anatomy/joint_roles.hpp"
#include "common/thread_pool.hpp"
#include "fitting/explained.hpp"
#include "fitting/kinematics.hpp"
#include "synthesis/body.hpp"

#include <cstdint>
#include <vector>

namespace ssc::fitting {

// The wrist on an elbow: the hand joint whose parent it is; lin.J when the rig has none.
uint32_t wrist_on(const LinearModel& lin, std::size_t elbow);

// Searches both arms of one frame and sets the chosen elbow and wrist rotations. kin and body:
// scratch for the frame's model (their state is overwritten). Returns whether a wrist moved.
// Rigs without limited elbow and wrist joints are left as they are.
bool search_wrists(Kinematics& kin, Body& body, FitState& state, const CloudView& cloud, const std::vector<uint32_t>& vertex_sample,
                   ThreadPool& pool);

// Turns the arm on `side` half a turn about the line from its upper arm's joint to its wrist: the
// whole arm rigidly, so the wrist stays where it is and the elbow swings round to the other side
// of that line. A straight arm turned over (palm and elbow facing the wrong way) lies on its points
// nearly as well as the right one, and neither the forearm's range nor a descent step turns it
// back; the solver tries this on fits that leave their scan a little way off
// (restart_if_off_closely in solver.cpp). Returns false, with the state as it was, when the rig
// has no such arm. kin: the frame's (updated here, without derivatives).
bool turn_arm_over(Kinematics& kin, FitState& state, anatomy::Side side);

}  // namespace ssc::fitting
