// A fit state as a posed mesh, through the runtime's float synthesis (the fast path; the double
// kinematics agree with it to 1e-5 m). Used for correspondences, results and residuals.
#pragma once

#include "fitting/kinematics.hpp"
#include "synthesis/body.hpp"

namespace ssc::fitting {

// Gives `body` a fit's shape: the whole body's coefficients, then (from a LinearModel with
// segments) every segment's; the rest zero.
void set_fit_shape(Body& body, const std::vector<double>& shape);

// Poses `body` (of the state's model) with the state and writes scale * posed + translation into
// vertices (resized to V) and, when given, unit vertex normals.
void posed_surface(Body& body, const FitState& s, std::vector<Vector3d>& vertices, std::vector<Vector3d>* normals = nullptr);

}  // namespace ssc::fitting
