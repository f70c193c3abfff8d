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

#include "common/thread_pool.hpp"
#include "fitting/explained.hpp"
#include "fitting/kinematics.hpp"
#include "synthesis/body.hpp"

#include <cstdint>
#include <vector>

namespace ssc::fitting {

// Searches both arms of one frame and sets the chosen elbow and wrist rotations. kin and body:
// scratch for the frame's model (their state is overwritten). Returns whether a wrist moved.
// Rigs without limited elbow and wrist joints are left as they are.
bool search_wrists(Kinematics& kin, Body& body, FitState& state, const CloudView& cloud, const std::vector<uint32_t>& vertex_sample,
                   ThreadPool& pool);

}  // namespace ssc::fitting
