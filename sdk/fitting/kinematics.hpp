// The model as a differentiable function for fitting: posed surface points and their analytic
// Jacobians with respect to every fit parameter, in double precision.
//
// Parameters, in this order in every Jacobian row:
//   shape     K coefficients (standard deviations)
//   rotation  3 per joint: a small rotation w (radians, world frame) applied to the joint's posed
//             world rotation, about the joint's posed position; children follow. The update of the
//             stored local pose is P <- exp(A^T w) P with A = parent world rotation * rest orientation.
//   translation 3 (metres), then log scale 1.
// A surface point is final = scale * v + translation, v the linear-blend-skinned model point.
#pragma once

#include "anatomy/model_anatomy.hpp"
#include "synthesis/model.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace ssc::fitting {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// What the fitter solves for.
struct FitState {
    // K: the used whole-body components (the rest stay zero), then, from a LinearModel with
    // segments, every segment's coefficients (posed_surface.hpp's set_fit_shape).
    std::vector<double> shape;
    std::vector<Eigen::Quaterniond> pose;     // J local pose rotations (each joint's rest frame)
    Vector3d translation = Vector3d::Zero();  // metres
    double scale = 1;
    // How closed each hand is (left, right; 0 open, 1 a fist: anatomy/hand_closure.hpp), chosen by
    // the hand search: the finger rotations' prior is centred on it.
    double hand_closure[2] = {0, 0};
};

// A point on the template: up to 3 vertices with barycentric weights (a vertex is one weight of 1).
struct SurfacePoint {
    uint32_t vertex[3] = {0, 0, 0};
    double weight[3] = {1, 0, 0};
};

// Model landmark l as a point of the template (its vertex, or its triangle's corners with the
// barycentric weights).
SurfacePoint landmark_point(const format::ModelData& model, uint32_t l);

// The joint with the largest skinning weight on vertex v (the first of equals): the part the
// vertex belongs to, for the judgement's regions, the interpenetration test and the tips.
uint32_t dominant_joint(const format::ModelData& model, uint32_t v);

// The model's linear parts in double precision for the used components: built once, shared by every
// frame's Kinematics.
struct LinearModel {
    // anatomy: the model's (shared, read-only); null: derived here. segments: the model's segment
    // shape spaces (when it has them) join as further components after all of the whole body's,
    // so a fit's shape holds the whole body's coefficients, then every segment's; those of the
    // segments named in left_out keep zero columns (their coefficients stay 0).
    LinearModel(const Model& model, uint32_t components, std::shared_ptr<const anatomy::ModelAnatomy> anatomy = nullptr,
                bool segments = false, const std::vector<std::string>& left_out = {});
    const Model& model;
    uint32_t K, J, V;
    uint32_t whole_body;  // the first K that are the whole body's components (K without segments)
    // The shape basis as the model stores it (quantized), laid out per vertex: [v][axis][k], each
    // value times step[k] in metres per standard deviation. A quarter of the memory of doubles,
    // which matters because fits read it at random vertices.
    std::vector<int16_t> basis;
    std::vector<double> step;  // [k]
    std::vector<double> joint_basis;  // [j][axis][k]
    std::vector<Vector3d> joint_mean;
    std::vector<Matrix3d> rest_orient;  // R_j (local rest orientation)
    std::vector<Matrix3d> rest_world;   // W_j = W_parent R_j
    std::vector<std::vector<uint32_t>> chains;  // ancestors of each joint, itself first
    std::shared_ptr<const anatomy::ModelAnatomy> anatomy;
    const std::vector<anatomy::JointLimit>& limits;  // per joint: anatomy->limits
    const std::vector<anatomy::JointRole>& roles;    // per joint: anatomy->roles
};

class Kinematics {
public:
    explicit Kinematics(const LinearModel& lin);

    const Model& model() const { return model_; }
    const LinearModel& linear() const { return lin_; }
    uint32_t components() const { return K_; }
    uint32_t joints() const { return J_; }
    // Parameter layout.
    uint32_t parameter_count() const { return K_ + 3 * J_ + 4; }
    uint32_t rotation_offset(uint32_t joint) const { return K_ + 3 * joint; }
    uint32_t translation_offset() const { return K_ + 3 * J_; }
    uint32_t scale_offset() const { return K_ + 3 * J_ + 3; }

    FitState zero_state() const;

    // Recomputes the skeleton for a state (cheap: joints only). Must precede the queries below.
    // Without derivatives (for cost-only evaluations) point_jacobian is unavailable until the next
    // update with them.
    void update(const FitState& s, bool derivatives = true);

    Vector3d rest_vertex(uint32_t v) const;                  // unposed, current shape
    Vector3d point(const SurfacePoint& p) const;             // final (scaled, translated)
    // Vertex v posed from its unposed position u (rest_vertex(v), cached by callers that pose the
    // same vertices many times), final frame; and its blended skinning rotation sum_j w_j S_j,
    // which carries unposed normals to posed ones (up to normalisation).
    Vector3d posed_vertex(uint32_t v, const Vector3d& u) const;
    Matrix3d skin_rotation(uint32_t v) const;
    // Joint j's skinning transform (a vertex skinned by j alone is S u + c before scale and
    // translation), and the global scale and translation: for callers that blend many vertices.
    const Matrix3d& joint_skin_rotation(uint32_t j) const { return skin_rot_[j]; }
    const Vector3d& joint_skin_translation(uint32_t j) const { return skin_trans_[j]; }
    double scale() const { return scale_; }
    const Vector3d& translation() const { return translation_; }
    // Adds d(final point)/d(parameters) (3 x parameter_count) into J (3 rows,
    // leading dimension = parameter_count, row-major) for the given point. `active`, when given
    // (parameter_count flags), skips the columns that are off: shape columns past the first off
    // one (stages use a prefix of the components) and the rotations of joints that are off; the
    // skipped entries are left as they were. Returns point(p), which it computes on the way.
    Vector3d point_jacobian(const SurfacePoint& p, double* J3, const uint8_t* active = nullptr) const;

    // Posed joint positions (final frame).
    Vector3d joint_position(uint32_t j) const { return scale_ * posed_joint_[j] + translation_; }
    // Rotation that maps a world-frame increment to the joint's local pose increment (A^T above).
    Matrix3d local_from_world(uint32_t j) const { return pre_pose_[j].transpose(); }

    // Applies an increment (parameter_count values) to a state: the retraction matching the Jacobians.
    void apply(const double* delta, FitState& s) const;

    // The parameters a point's Jacobian can touch (sorted): shape, its joints' chains, translation, scale.
    void nonzeros(const SurfacePoint& p, std::vector<uint32_t>& out) const;

private:
    Vector3d skinned(uint32_t v, const Vector3d& u) const;  // linear blend skinning, before scale and translation
    // Returns the skinned vertex (before scale and translation).
    Vector3d vertex_jacobian(uint32_t v, double* J3, double factor, uint32_t shape_columns, const uint8_t* active) const;

    const LinearModel& lin_;
    const Model& model_;
    uint32_t K_, J_;
    // Current state.
    std::vector<double> shape_;
    std::vector<double> weighted_shape_;  // step[k] * shape_[k]: multiplies the quantized basis
    // rest_vertex() sums the first this many terms: the nonzero ones (the coarse stages fit the first
    // few components only), rounded up to dot_quantized's block of 8 so the sums stay bit-identical.
    uint32_t shape_terms_ = 0;
    double scale_ = 1;
    bool derivatives_ = false;  // whether the last update computed the shape derivatives
    Vector3d translation_ = Vector3d::Zero();
    std::vector<Vector3d> rest_joint_, posed_joint_;
    std::vector<double> rest_joints_shape_;  // the shape rest_joint_ was computed for
    bool rest_joints_valid_ = false;
    std::vector<Matrix3d> world_, pre_pose_, skin_rot_;  // G_j, G_parent R_j, S_j = G_j W_j^T
    std::vector<Vector3d> skin_trans_;                   // c_j
    std::vector<double> dpos_, dskin_;
    mutable std::vector<uint8_t> seen_;  // nonzeros() scratch                   // d posed joint / d shape, d c_j / d shape: [j][axis][k]
};

}  // namespace ssc::fitting
