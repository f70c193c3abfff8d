// A mesh in the model's topology that the model did not make (a registered scan brought to rest, a
// body edited in another tool) as a body the measurer takes: in the model's frame and with joints.
#pragma once

#include "synthesis/model.hpp"

#include <Eigen/Core>

#include <vector>

namespace ssc::measure {

// Farther than this (metres) from the model's nearest body, a mesh is posed or not a body of the
// model. Measured (tests/test_measure.cpp): the model's own bodies at rest 0.1 mm, MakeHuman people it
// does not hold at rest 8-14 mm, the same people in a booth's posture (10 degrees) 12-15 mm, a
// body with both arms turned 0.6 rad 92 mm. It tells gross posture, not a booth's.
inline constexpr double kFarFromShapeSpace = 0.02;

struct MeshBody {
    std::vector<float> xyz;     // 3V, the model's frame (metres, +Y up, facing +Z)
    std::vector<float> joints;  // 3J, placed by the model's joint regressor
    // Metres, root mean square over the vertices: how far the aligned mesh lies from the nearest body
    // of the model's shape space (least squares over its components and a small rigid motion).
    double off_shape_space = 0;
};

// `vertices` (metres, the model's vertex order, any frame) turned and moved, by the one rigid motion
// that fits best, onto the nearest body of the model's shape space (measurements read heights along
// +Y), its joints placed by the regressor the model places its own joints with. The mesh is measured
// in the posture it has: a posed body gives posed figures (off_shape_space tells gross posture).
// Throws ssc::Error (INVALID_ARGUMENT) for another vertex count or non-finite coordinates.
MeshBody mesh_body(const Model& model, const std::vector<Eigen::Vector3d>& vertices);

}  // namespace ssc::measure
