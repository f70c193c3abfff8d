// A picture of a registration beside its scan: the scan's points, then the registered template
// coloured by a per-vertex error (green within 1 mm, through yellow at 5 mm, to red at 10 mm and
// beyond; grey where there is none), each from the front and the side.
#pragma once

#include "synthesis/model.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace ssc::render {

// frame: the rotation and origin that turn the scan's coordinates into the model's upright,
// front-facing frame (world = frame_R * model + frame_t). error: per vertex, metres, or negative
// for none.
void write_registration_picture(const std::string& path, const Model& model, const Eigen::Matrix3d& frame_R,
                                const Eigen::Vector3d& frame_t, const std::vector<Eigen::Vector3d>& points,
                                const std::vector<Eigen::Vector3d>& registered, const std::vector<double>& error);

}  // namespace ssc::render
