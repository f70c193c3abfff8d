// Posture normalization: bringing a registered scan to the model's rest posture before PCA, so that
// the shape space learns body shape and not how each person stood in the booth.
#pragma once

#include "fitting/kinematics.hpp"
#include "synthesis/model.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace ssc::learning {

enum class Posture {
    None,      // the registrations as they are (rigidly aligned only)
    Skeleton,  // each one's skinning undone with its own fitted skeleton and pose
    Laplacian, // rebuilt from posture-free differential coordinates (laplacian_posture.hpp); no fit needed
};

// "none", "skeleton" or "laplacian"; throws ssc::Error (INVALID_ARGUMENT) for any other name.
Posture posture_from_name(const std::string& name);
const char* posture_name(Posture p);

// The skeleton method: `posed` (the model's vertex order, in the fit's frame, metres) brought to
// the rest posture of the fit's own shape. Each vertex's blended skinning transform (its joints'
// transforms for the fit's shape and pose, weighted as the model skins it) is inverted, so a
// registration equal to the fitted body comes back as the fitted shape at rest exactly, and what
// the registration adds to the fit stays, turned back with the vertex's own transform.
// Throws ssc::Error (INVALID_ARGUMENT) for a wrong vertex count, a fit of another model's size or
// non-finite values.
std::vector<Eigen::Vector3d> unpose_skeleton(const Model& model, const fitting::FitState& fit, const std::vector<Eigen::Vector3d>& posed);

}  // namespace ssc::learning
