// A model fit's parameters as JSON: one versioned format for every file that holds a fit, so each
// reads the others'. `sscape fit --params` (ssc_fitter_write_params) writes it whole, a
// registration's report and a posture fit hold it under "fit". Version 2:
//   {"format": "sscape fit parameters 2", "model": NAME, "model_digest": HEX (when known),
//    "shape": [the whole body's coefficients], "segment_shape": [every segment's] (when fitted),
//    "frames": [{"rotations_xyzw": {JOINT: [x, y, z, w], ...}, "translation_m": [x, y, z],
//                "scale": s}, ...]}
// in the fit's frame (the scan's, turned so that its up axis is +Y), metres. Read besides: version 1
// (`sscape fit --params` until now: the same without segment_shape) and the layout of earlier
// registration reports and posture fits (no format; one frame, its fields at the top level,
// rotations_xyzw one array in joint order). Internal to the offline tools (it includes nlohmann/json).
#pragma once

#include "fitting/kinematics.hpp"
#include "synthesis/model.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace ssc::scan_files {

inline constexpr const char* kFitParamsFormat = "sscape fit parameters 2";

// The frames' shared shape is frames[0].shape. model_digest: the digest of the model's file, empty
// when not known (then not written).
nlohmann::ordered_json fit_params_to_json(const Model& model, const std::vector<fitting::FitState>& frames, const std::string& model_digest = "");
nlohmann::ordered_json fit_to_json(const Model& model, const fitting::FitState& fit, const std::string& model_digest = "");

struct FitParams {
    std::string model_name, model_digest;   // as the file gives them (empty when absent)
    std::vector<fitting::FitState> frames;  // at least one, each with the shared shape
};

// Every frame of a fit of `model` (whose file's digest is model_digest; empty: not checked). Joints
// a version 1 or 2 file does not name keep the rest pose; a shape may hold fewer coefficients than
// the model's components. Throws ssc::Error INVALID_ARGUMENT, naming the value, for a fit of
// another model (by digest, or by name where the file has no digest), a format of another version,
// unknown joints, sizes that do not match the model, and values no fit gives: not finite, shape
// coefficients beyond +-kShapeLimit, a scale outside [0.1, 10], a translation beyond 1e6 m,
// rotations that are not unit quaternions; nlohmann::json::exception for a malformed object.
FitParams fit_params_from_json(const nlohmann::ordered_json& j, const Model& model, const std::string& model_digest = "");

// Why a fit file is not a fit of `model` (whose file's digest is model_digest): "fitted with the model
// 'NAME' (digest HEX), not this one (...)"; empty when it is, or cannot be told. What
// fit_params_from_json refuses first, for callers that report it apart from malformed files.
std::string other_model(const nlohmann::ordered_json& j, const Model& model, const std::string& model_digest);

// Frame 0 of fit_params_from_json.
fitting::FitState fit_from_json(const nlohmann::ordered_json& j, const Model& model);

}  // namespace ssc::scan_files
