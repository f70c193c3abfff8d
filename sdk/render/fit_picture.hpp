// A picture of a fit next to its input: the measured points, the fitted body, and (for simulated
// data) the true body, each from the front and the side of the fitted body's own frame.
#pragma once

#include "fitting/solver.hpp"

#include <string>
#include <vector>

namespace ssc::render {

// points: the input (scan points and landmarks, any frame); fitted/truth: posed vertices in that
// frame (truth may be empty). The fit's root rotation, scale and translation define the frame the
// picture is drawn in, so any heading of the input comes out facing the viewer.
void write_fit_picture(const std::string& path, const Model& model, const fitting::FitState& fit,
                       const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& fitted,
                       const std::vector<Eigen::Vector3d>& truth);

}  // namespace ssc::render
