// The fitter's search over how closed each hand is, after the limb search.
//
// Why: scanned people hold their hands relaxed or in fists, the model's are spread open, and the
// fingers' tight prior (solver.cpp) keeps a fit's fingers near wherever they start: the hands were
// the largest residual of good fits. After the fine stage (the wrists in place), each hand tries
// closures 0, 0.25, .. 1 (anatomy/hand_closure.hpp), then halfway to the best one's neighbours,
// scored with the explained measure of the hand alone (LimbScore of the hand joint), keeping the
// current fingers unless a closure gains a little (kMinGain in hand_search.cpp); when a hand
// changed, the fine stage runs again, the fingers' prior centred on the closure. In a single
// frame's fit from its own start the solver keeps the closures only when the whole fit then lies
// closer to the scan (keep_if_closer in solver.cpp): on a hand the stages before left off its
// points, the measure prefers a fist (docs/fitting.md).
#pragma once

#include "fitting/explained.hpp"
#include "fitting/kinematics.hpp"
#include "synthesis/body.hpp"

#include <cstdint>
#include <vector>

namespace ssc::fitting {

// Searches both hands of one frame and sets the chosen closures' finger rotations and
// state.hand_closure. kin and body: scratch for the frame's model (their state is overwritten).
// Rigs without the hand joints are left as they are.
void search_hands(Kinematics& kin, Body& body, FitState& state, const CloudView& cloud, const std::vector<uint32_t>& vertex_sample);

// Sets hand (0 left, 1 right) of state to the closure (its finger rotations and hand_closure).
// Rigs without the hand's joints are left as they are.
void set_hand_closure(const Model& model, FitState& state, int hand, double closure);

}  // namespace ssc::fitting
