// Normals of scan points the input did not give: scanners and meshing tools leave some zero or
// drop them; the fitter needs one per point for its point-to-plane and normal-compatibility terms.
#pragma once

#include "nearest.hpp"

#include <Eigen/Core>

#include <vector>

namespace ssc::fitting {

// Replaces each zero normal by the plane fitted to its 12 nearest points. Its sign is taken from the
// given (non-zero on entry) normals among those neighbours. Returns true when every estimated
// normal found such a neighbour (the set stays oriented); false when some normal's sign is a guess
// (then callers must ignore all signs). index is built over points.
bool estimate_missing_normals(const std::vector<Eigen::Vector3d>& points, const PointIndex& index, std::vector<Eigen::Vector3d>& normals);

}  // namespace ssc::fitting
