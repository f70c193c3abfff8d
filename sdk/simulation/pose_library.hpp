// The benchmark's pose library: the postures people take in front of a scanner and in everyday
// life, over the full range of motion (kneeling, squatting, sitting on a chair and on the floor,
// lying, bending to the toes, reaching, twisting, arms crossed and other touching limbs, walking
// and running steps). Each pose is anatomical joint angles (anatomy::JointAngles), within the
// joints' anatomical limits, so it serves any model with the game-engine joint names; the named
// poses (anatomy/named_poses) are among them.
#pragma once

#include "anatomy/named_poses.hpp"
#include "synthesis/model.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace ssc::simulation {

struct LibraryPose {
    std::string name;         // snake_case
    std::string description;
    std::string named;        // a named pose it is (anatomy::named_pose), or empty
    std::vector<anatomy::JointAngles> angles;  // otherwise its angles
    // Degrees the posed body is turned as a whole (lying): pitched forward about the body's
    // left-right axis, then rolled to its right about the forward axis.
    double pitch = 0, roll = 0;
};

// A library pose on a body leaves less than this share of each forearm and lower leg inside
// another part of the body (fitting/interpenetration.hpp): people cannot pass through themselves.
// The benchmark redraws a pose's random variation that does.
constexpr double kLibraryInside = 0.05;

// Every pose of the library, a fixed order.
const std::vector<LibraryPose>& pose_library();

// A library pose's local joint rotations for the model (4 floats per joint, x y z w).
std::vector<float> library_pose(const Model& model, const LibraryPose& pose);

// The rotation that turns the posed body as the pose says (identity for all but the lying poses),
// about the origin of the model's frame (x left, y up, z forward).
Eigen::Matrix3d library_orientation(const LibraryPose& pose);

}  // namespace ssc::simulation
