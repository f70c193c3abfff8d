// A model fit (shape, pose, translation, scale) as JSON: how a registration's report and a posture
// fit's file store it. Internal to the learning library (it includes nlohmann/json).
#pragma once

#include "fitting/kinematics.hpp"
#include "synthesis/model.hpp"

#include <nlohmann/json.hpp>

namespace ssc::scan_files {

// The whole body's coefficients ("shape"), then the segments' ("segment_shape") when the fit had
// them; rotations as x y z w per joint; translation in metres.
nlohmann::ordered_json fit_to_json(const Model& model, const fitting::FitState& fit);

// Throws ssc::Error (INVALID_ARGUMENT) for sizes that do not match the model or values that are
// not finite, nlohmann::json::exception for a malformed object.
fitting::FitState fit_from_json(const nlohmann::ordered_json& j, const Model& model);

}  // namespace ssc::scan_files
