// A change of a fit's shape that makes one forearm longer or shorter: what the fitter tries when
// the hand search has closed a hand (solver.cpp, docs/fitting.md "A forearm fitted too long").
//
// Why: a straight forearm's surface hardly shows where the wrist is. When a fit's forearm comes
// out a few centimetres too long (a person's forearm shorter than the model's proportions make
// it), the hand closes so that it ends at the scan's fingertips, and no descent step leaves that
// state: opening the hand alone overshoots the fingertips. Moving the wrist back along the forearm
// with the hand opened does.
#pragma once

#include "fitting/kinematics.hpp"

#include <vector>

namespace ssc::fitting {

// The shape change (one value per component of lin) that moves the wrist of `hand` (0 left, 1
// right: the model's hand_l or hand_r joint) by `metres` along its forearm (from the elbow, its
// parent joint, towards it; negative: shorter) in the rest skeleton of `shape`, every joint outside
// the hand held where it is: least squares over all of lin's components, with a small ridge so that
// the change is the least one. Empty when the model has no such joint, or when its components
// cannot make that forearm alone longer or shorter (the joints would miss by over a quarter of the
// move: a whole-body shape space without the arms' segment spaces).
std::vector<double> forearm_length_change(const LinearModel& lin, const std::vector<double>& shape, int hand, double metres);

}  // namespace ssc::fitting
