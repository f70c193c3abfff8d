// Synthetic measurements of model bodies with known ground truth: random plausible bodies and
// poses, landmarks with placement noise, scan point clouds with noise, holes and outliers. Tests
// and benchmarks measure the fitter's accuracy with them.
#pragma once

#include "fitting/solver.hpp"

#include <random>
#include <vector>

namespace ssc::simulation {

struct TrueBody {
    std::vector<float> shape;                      // model's K coefficients
    std::vector<float> pose;                       // 4J quaternions xyzw (local)
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> vertices;         // posed
    std::vector<Eigen::Vector3d> normals;          // posed, unit
    std::vector<Eigen::Vector3d> landmarks;        // posed
};

// Shape coefficients drawn from the model's own distribution (standard normal), clipped at 2.5 SD.
std::vector<float> random_shape(const Model& m, std::mt19937& rng);

// A plausible pose: trunk bent and twisted, head turned, arms raised or swung with the elbows bent,
// hips flexed or spread with the knees bent, within everyday ranges. Angles are drawn in the body's
// frame (x left, y up, z forward) and converted to each joint's rest frame. amount scales them.
std::vector<float> random_pose(const Model& m, std::mt19937& rng, double amount = 1.0);

// A person standing in a booth scanner as told, with the variation people bring: the rest posture
// with each upper arm raised or lowered from it by up to `spread` degrees, each elbow bent or
// straightened by up to `spread`, the head tilted and turned by up to half of it, and the feet set
// apart by up to half of it. Angles are anatomical (anatomy/joint_limits.hpp).
std::vector<float> scanning_pose(const Model& m, std::mt19937& rng, double spread = 10.0);

// Poses the body (Body, the runtime's synthesis) and fills vertices, normals and landmarks.
TrueBody make_body(const Model& m, std::vector<float> shape, std::vector<float> pose, const Eigen::Vector3d& translation);

// Rotates and translates a body as a whole (a different facing direction or camera frame).
// A body from rest vertices that are not the model's (another body of the template's topology, such
// as a MakeHuman body with targets the model was not trained on), posed by the model's skeleton
// (regressed from those vertices) and skinning. pose: 4J quaternions x y z w.
TrueBody pose_rest_vertices(const Model& m, const std::vector<Eigen::Vector3d>& rest, std::vector<float> pose,
                            const Eigen::Vector3d& translation);

void transform_body(TrueBody& b, const Eigen::Matrix3d& R, const Eigen::Vector3d& t);

// The model's landmarks with isotropic Gaussian noise (sd metres), optionally without the six hand
// landmarks of ../shared/docs/landmarks.md (37, 38, 40, 49, 50, 52).
std::vector<fitting::LandmarkTarget> simulate_landmarks(const Model& m, const TrueBody& b, double sd, bool skip_hands,
                                                        std::mt19937& rng);

struct CloudSpec {
    uint32_t points = 20000;
    double noise = 0.002;           // metres, along the normal and tangentially (isotropic)
    double missing = 0.2;           // fraction of the surface removed, as 20 round holes
    double outliers = 0.01;         // fraction of points replaced by uniform clutter around the body
    bool normals = true;            // give each surface point its surface normal (outliers random)
};

// Points drawn uniformly over the posed surface (by triangle area).
fitting::PointCloud simulate_cloud(const Model& m, const TrueBody& b, const CloudSpec& spec, std::mt19937& rng);

// Bumps and dents the model cannot represent: `count` Gaussian displacements along the normal,
// 1 to 2 cm high and 4 to 10 cm wide, at random vertices; the normals follow.
void add_bumps(TrueBody& b, const Model& m, int count, std::mt19937& rng);

// Mean distance between corresponding vertices of two posed meshes.
double mean_vertex_error(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b);

// The posed vertices of a fit result (through Body, independent of the fitter's own kinematics).
std::vector<Eigen::Vector3d> fitted_vertices(const Model& m, const fitting::FitState& s);

// How closely the model can represent a body at all: the mean vertex distance of `rest` (the
// model's vertex order, rest pose) to its least-squares approximation by the model's shape space
// and a translation, correspondence known; first rigidly aligned onto the model's mean when
// `align` (as learning aligns its bodies). A registration that follows the surface from the model
// fit cannot be expected to get much below it along the surface. `approximation`, when given,
// receives the approximation itself (in `rest`'s frame after the alignment). `with_segments`: the
// model's segment shape spaces join the whole body's (all coefficients solved together).
double best_approximation_error(const Model& m, std::vector<Eigen::Vector3d> rest, bool align,
                                std::vector<Eigen::Vector3d>* approximation = nullptr, bool with_segments = false);

}  // namespace ssc::simulation
