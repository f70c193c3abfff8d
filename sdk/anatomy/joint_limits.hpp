// Anatomical joint limits (the fitter's pose prior, named poses, pose checks): the range of motion of each joint in an
// anatomical frame (flexion/extension, axial rotation, abduction/adduction), so that fits cannot
// reach bodies no person can take (a knee bent forwards, a thigh turned half round), the local
// minima of fitting sparse or partial data.
//
// Frame of a joint (world, rest pose): y' along the bone (the rig puts each joint's +Y there),
// x' the flexion axis (the body's left-right axis, or for the arm the axis across the arm in the
// frontal plane, as the rest pose holds the arms out), z' = x' × y'. A local pose rotation P has
// the anatomical components c = A^T W log(P) (W the joint's rest world rotation, A = [x' y' z']);
// for right-side joints the y' and z' components are negated, so one table serves both sides.
// Components are compared with [lo, hi] per axis, radians, relative to the rest pose.
//
// Sources: the ranges follow the American Academy of Orthopaedic Surgeons' average ranges of
// motion (AAOS, Joint Motion: Method of Measuring and Recording, 1965, as tabulated by Greene &
// Heckman, The Clinical Measurement of Joint Motion, AAOS 1994): hip flexion 120°, extension 30°,
// abduction 45°, adduction 30°, rotation 45° each way; knee flexion 135°; ankle dorsiflexion 20°,
// plantar flexion 50°; shoulder flexion 180°, extension 60°, abduction 180°, rotation 70-90°;
// elbow flexion 150°; forearm rotation 80° each way; wrist flexion 80°, extension 70°, deviation
// 20-30°; thoracolumbar flexion 80°, extension 25°, lateral bending 35°, rotation 45°; cervical
// flexion and extension 45°, lateral bending 45°, rotation 60°. Spinal motion is split over the
// rig's spine joints, and every range gets a small margin (the rotation-vector components only
// approximate the clinical angles at large rotations).
//
// Training computes the limits from this table and stores them in the model file; the runtime
// reads them from there, so a model may carry its own.
#pragma once

#include "synthesis/model.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace ssc::anatomy {

using Eigen::Matrix3d;
using Eigen::Vector3d;

struct JointLimit {
    bool limited = false;
    Matrix3d to_anatomical = Matrix3d::Identity();  // c = to_anatomical * log(local pose)
    Vector3d lo = Vector3d::Zero(), hi = Vector3d::Zero();  // radians: flexion (x'), axial (y'), abduction (z')
};

// The limits of the range-of-motion table above for a skeleton (training: they are stored in the
// model file). Joints the table does not name (root, pelvis, fingers) get none (the fitter's
// rotation prior holds the fingers). Sorted by joint.
std::vector<format::JointLimit> compute_joint_limits(const format::Skeleton& skeleton);

// One entry per joint of the model, from the limits its file stores (none: nothing limited).
std::vector<JointLimit> joint_limits(const Model& model);

// The anatomical components of a joint's local pose rotation.
Vector3d anatomical_angles(const JointLimit& limit, const Eigen::Quaterniond& local_pose);

// The local pose rotation with the given anatomical angles (radians): the inverse of
// anatomical_angles (the frame is a rotation, so log(P) = frame^T angles).
Eigen::Quaterniond rotation_from_angles(const JointLimit& limit, const Vector3d& angles);

// Whether a local pose rotation lies outside the limit (beyond a 1e-5 rad tolerance); with clamp,
// also moves each anatomical angle into its range and rewrites the rotation.
bool enforce_limit(const JointLimit& limit, Eigen::Quaterniond& local_pose, bool clamp);

}  // namespace ssc::anatomy
