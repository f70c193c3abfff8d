// Forward kinematics and analytic Jacobians of the skinned model (see kinematics.hpp).
//
// The skeleton follows kernels_pose.cpp: rest world rotation W_j = W_parent R_j, posed world
// rotation G_j = G_parent R_j P_j, posed joint position q_j = S_parent (p_j - p_parent) + q_parent
// (root: q = p), skinning rotation S_j = G_j W_j^T and translation c_j = q_j - S_j p_j, so a vertex
// is v = sum_a w_a (S_a u + c_a) for rest position u = mean + basis * shape.
//
// Shape derivatives: dq_j = S_parent (dp_j - dp_parent) + dq_parent, dc_j = dq_j - S_j dp_j, with
// dp the joint regressor applied to the basis. Rotation derivatives: turning joint k by w about q_k
// moves every part skinned by k or a descendant: dv = w x a_k with
// a_k = sum over those influences of w_a (S_a u + c_a - q_k).
#include "fitting/kinematics.hpp"

#include "common/error.hpp"
#include "synthesis/shape_range.hpp"

#include <algorithm>
#include <cmath>

namespace ssc::fitting {

namespace {

// sum_k a[k] b[k], with partial sums as dot_quantized below.
double dot(const double* a, const double* b, uint32_t n) {
    double acc[4] = {0, 0, 0, 0};
    std::size_t k = 0;
    for (; k + 4 <= n; k += 4)
        for (std::size_t i = 0; i < 4; ++i) acc[i] += a[k + i] * b[k + i];
    for (; k < n; ++k) acc[0] += a[k] * b[k];
    return (acc[0] + acc[2]) + (acc[1] + acc[3]);
}

// sum_k q[k] w[k]. Eight independent partial sums: a single running sum is one long dependency
// chain the compiler may not reorder (strict floating point), and was the fitter's largest cost.
double dot_quantized(const int16_t* q, const double* w, uint32_t n) {
    double acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    std::size_t k = 0;
    for (; k + 8 <= n; k += 8)
        for (std::size_t i = 0; i < 8; ++i) acc[i] += double(q[k + i]) * w[k + i];
    for (; k < n; ++k) acc[0] += double(q[k]) * w[k];
    return ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7]));
}

Eigen::Quaterniond exp_rotation(const Vector3d& w) {
    const double angle = w.norm();
    if (angle < 1e-12) return Eigen::Quaterniond(1, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z()).normalized();
    return Eigen::Quaterniond(Eigen::AngleAxisd(angle, w / angle));
}

}  // namespace

uint32_t dominant_joint(const format::ModelData& d, uint32_t v) {
    const std::size_t at = 4 * std::size_t(v);
    int best = 0;
    for (int i = 1; i < 4; ++i)
        if (d.skin.weights[at + std::size_t(i)] > d.skin.weights[at + std::size_t(best)]) best = i;
    return d.skin.joints[at + std::size_t(best)];
}

SurfacePoint landmark_point(const format::ModelData& d, uint32_t l) {
    const auto& lm = d.landmarks[l];
    SurfacePoint p;
    if (lm.vertex != format::kNone) {
        p.vertex[0] = lm.vertex;
        return p;
    }
    for (int i = 0; i < 3; ++i) {
        p.vertex[i] = d.mesh.triangles[3 * std::size_t(lm.triangle) + std::size_t(i)];
        p.weight[i] = lm.barycentric[i];
    }
    return p;
}

LinearModel::LinearModel(const Model& m, uint32_t components, std::shared_ptr<const anatomy::ModelAnatomy> shared, bool segments,
                         const std::vector<std::string>& left_out)
    : model(m), K(std::min(components, m.component_count())), J(m.joint_count()), V(m.vertex_count()), whole_body(K),
      anatomy(shared ? std::move(shared) : std::make_shared<const anatomy::ModelAnatomy>(m)), limits(anatomy->limits),
      roles(anatomy->roles) {
    const auto& d = m.data();
    const std::vector<SegmentSpace>& spaces = m.segments();
    if (segments && !spaces.empty()) {
        SSC_REQUIRE_ARG(whole_body == m.component_count(), "linear model: segments follow all of the whole body's components");
        K = whole_body + uint32_t(m.segment_coefficient_count());
    }
    const float* step_in = m.basis_step();
    step.assign(step_in, step_in + whole_body);
    basis.assign(std::size_t(V) * 3 * K, 0);
    for (uint32_t k = 0; k < whole_body; ++k)
        for (uint32_t a = 0; a < 3; ++a)
            for (uint32_t v = 0; v < V; ++v) basis[(std::size_t(v) * 3 + a) * K + k] = d.shape.basis.q[(std::size_t(k) * 3 + a) * V + v];
    joint_basis.assign(std::size_t(J) * 3 * K, 0.0);
    joint_mean.resize(J);
    for (uint32_t j = 0; j < J; ++j)
        for (uint32_t a = 0; a < 3; ++a) {
            joint_mean[j][a] = m.joint_mean()[3 * j + a];
            for (uint32_t k = 0; k < whole_body; ++k)
                joint_basis[(std::size_t(j) * 3 + a) * K + k] = double(step[k]) * m.joint_basis()[(std::size_t(k) * J + j) * 3 + a];
        }
    // Segment components, quantized like the whole body's (16 bits over each one's largest value).
    if (K > whole_body)
        for (const SegmentSpace& seg : spaces) {
            if (std::find(left_out.begin(), left_out.end(), seg.name) != left_out.end()) {  // zero columns: kept at 0 by the prior
                step.insert(step.end(), seg.components, 1.0);
                continue;
            }
            const std::size_t n = seg.vertices.size();
            for (uint32_t c = 0; c < seg.components; ++c) {
                const uint32_t k = whole_body + seg.first + c;
                float largest = 0;
                for (std::size_t i = 0; i < 3 * n; ++i) largest = std::max(largest, std::abs(seg.basis[std::size_t(c) * 3 * n + i]));
                const double q = largest > 0 ? double(largest) / 32767 : 1.0;
                step.push_back(q);
                for (uint32_t a = 0; a < 3; ++a)
                    for (std::size_t i = 0; i < n; ++i)
                        basis[(std::size_t(seg.vertices[i]) * 3 + a) * K + k] =
                            int16_t(std::lround(double(seg.basis[(std::size_t(c) * 3 + a) * n + i]) / q));
                for (uint32_t j = 0; j < J; ++j)
                    for (uint32_t a = 0; a < 3; ++a)
                        joint_basis[(std::size_t(j) * 3 + a) * K + k] = seg.joint_basis[(std::size_t(c) * J + j) * 3 + a];
            }
        }
    rest_orient.resize(J);
    rest_world.resize(J);
    chains.resize(J);
    for (uint32_t j = 0; j < J; ++j) {
        const float* q = &d.skeleton.rest_orientations[4 * j];
        rest_orient[j] = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
        const int32_t parent = d.skeleton.parents[j];  // parents precede children
        rest_world[j] = parent < 0 ? rest_orient[j] : Matrix3d(rest_world[uint32_t(parent)] * rest_orient[j]);
        for (int32_t a = int32_t(j); a >= 0; a = d.skeleton.parents[uint32_t(a)]) chains[j].push_back(uint32_t(a));
    }
}

Kinematics::Kinematics(const LinearModel& lin) : lin_(lin), model_(lin.model), K_(lin.K), J_(lin.J) {
    rest_joint_.resize(J_);
    posed_joint_.resize(J_);
    world_.resize(J_);
    pre_pose_.resize(J_);
    skin_rot_.resize(J_);
    skin_trans_.resize(J_);
    dpos_.assign(std::size_t(J_) * 3 * K_, 0.0);
    dskin_.assign(std::size_t(J_) * 3 * K_, 0.0);
    shape_.assign(K_, 0.0);
    weighted_shape_.assign(K_, 0.0);
}

void Kinematics::nonzeros(const SurfacePoint& p, std::vector<uint32_t>& out) const {
    out.clear();
    for (uint32_t k = 0; k < K_; ++k) out.push_back(k);
    const auto& skin = model_.data().skin;
    auto& seen = seen_;
    seen.assign(J_, 0);
    for (int b = 0; b < 3; ++b) {
        if (p.weight[b] == 0) continue;
        for (int i = 0; i < 4; ++i) {
            if (skin.weights[4 * std::size_t(p.vertex[b]) + i] == 0) continue;
            for (uint32_t k : lin_.chains[skin.joints[4 * std::size_t(p.vertex[b]) + i]]) seen[k] = 1;
        }
    }
    for (uint32_t j = 0; j < J_; ++j)
        if (seen[j])
            for (uint32_t c = 0; c < 3; ++c) out.push_back(rotation_offset(j) + c);
    for (uint32_t c = 0; c < 4; ++c) out.push_back(translation_offset() + c);
}

FitState Kinematics::zero_state() const {
    FitState s;
    s.shape.assign(K_, 0.0);
    s.pose.assign(J_, Eigen::Quaterniond::Identity());
    return s;
}

void Kinematics::update(const FitState& s, bool derivatives) {
    derivatives_ = derivatives;
    const auto& parents = model_.data().skeleton.parents;
    std::copy(s.shape.begin(), s.shape.begin() + K_, shape_.begin());
    shape_terms_ = 0;
    for (uint32_t k = 0; k < K_; ++k) {
        weighted_shape_[k] = lin_.step[k] * shape_[k];
        if (weighted_shape_[k] != 0) shape_terms_ = k + 1;
    }
    shape_terms_ = std::min(K_, (shape_terms_ + 7) / 8 * 8);
    scale_ = s.scale;
    translation_ = s.translation;
    // Rest joints depend on the shape only: pose-only updates (the limb search's candidates) keep them.
    if (!rest_joints_valid_ || rest_joints_shape_ != shape_) {
        for (uint32_t j = 0; j < J_; ++j) {
            Vector3d p = lin_.joint_mean[j];
            for (uint32_t a = 0; a < 3; ++a) p[a] += dot(lin_.joint_basis.data() + (std::size_t(j) * 3 + a) * K_, shape_.data(), K_);
            rest_joint_[j] = p;
        }
        rest_joints_shape_ = shape_;
        rest_joints_valid_ = true;
    }
    const std::vector<Matrix3d>& rest_world = lin_.rest_world;
    for (uint32_t j = 0; j < J_; ++j) {
        const Vector3d& p = rest_joint_[j];
        const Matrix3d P = s.pose[j].normalized().toRotationMatrix();
        const int32_t parent = parents[j];
        double* dq = dpos_.data() + std::size_t(j) * 3 * K_;
        const double* dp = lin_.joint_basis.data() + std::size_t(j) * 3 * K_;
        if (parent < 0) {
            pre_pose_[j] = lin_.rest_orient[j];
            posed_joint_[j] = p;
            if (derivatives) std::copy(dp, dp + 3 * K_, dq);
        } else {
            const auto up = uint32_t(parent);
            pre_pose_[j] = world_[up] * lin_.rest_orient[j];
            posed_joint_[j] = skin_rot_[up] * (p - rest_joint_[up]) + posed_joint_[up];
            const double* dpp = lin_.joint_basis.data() + std::size_t(up) * 3 * K_;
            const double* dqp = dpos_.data() + std::size_t(up) * 3 * K_;
            if (derivatives)
                for (std::size_t k = 0; k < K_; ++k) {
                    const Vector3d diff(dp[k] - dpp[k], dp[K_ + k] - dpp[K_ + k], dp[2 * K_ + k] - dpp[2 * K_ + k]);
                    const Vector3d r = skin_rot_[up] * diff;
                    for (std::size_t a = 0; a < 3; ++a) dq[a * K_ + k] = r[a] + dqp[a * K_ + k];
                }
        }
        world_[j] = pre_pose_[j] * P;
        skin_rot_[j] = world_[j] * rest_world[j].transpose();
        skin_trans_[j] = posed_joint_[j] - skin_rot_[j] * p;
        double* dc = dskin_.data() + std::size_t(j) * 3 * K_;
        if (derivatives)
            for (std::size_t k = 0; k < K_; ++k) {
                const Vector3d r = skin_rot_[j] * Vector3d(dp[k], dp[K_ + k], dp[2 * K_ + k]);
                for (std::size_t a = 0; a < 3; ++a) dc[a * K_ + k] = dq[a * K_ + k] - r[a];
            }
    }
}

Vector3d Kinematics::rest_vertex(uint32_t v) const {
    const float* mean = &model_.data().shape.mean[3 * std::size_t(v)];
    Vector3d u(mean[0], mean[1], mean[2]);
    for (uint32_t a = 0; a < 3; ++a) u[a] += dot_quantized(lin_.basis.data() + (std::size_t(v) * 3 + a) * K_, weighted_shape_.data(), shape_terms_);
    return u;
}

Vector3d Kinematics::point(const SurfacePoint& p) const {
    Vector3d out = Vector3d::Zero();
    for (int b = 0; b < 3; ++b)
        if (p.weight[b] != 0) out += p.weight[b] * skinned(p.vertex[b], rest_vertex(p.vertex[b]));
    return scale_ * out + translation_;
}

Vector3d Kinematics::skinned(uint32_t v, const Vector3d& u) const {
    const auto& skin = model_.data().skin;
    Vector3d x = Vector3d::Zero();
    for (int i = 0; i < 4; ++i) {
        const float w = skin.weights[4 * std::size_t(v) + i];
        const uint16_t j = skin.joints[4 * std::size_t(v) + i];
        if (w != 0) x += double(w) * (skin_rot_[j] * u + skin_trans_[j]);
    }
    return x;
}

Vector3d Kinematics::posed_vertex(uint32_t v, const Vector3d& u) const { return scale_ * skinned(v, u) + translation_; }

Matrix3d Kinematics::skin_rotation(uint32_t v) const {
    const auto& skin = model_.data().skin;
    Matrix3d m = Matrix3d::Zero();
    for (int i = 0; i < 4; ++i) {
        const float w = skin.weights[4 * std::size_t(v) + i];
        if (w != 0) m += double(w) * skin_rot_[skin.joints[4 * std::size_t(v) + i]];
    }
    return m;
}

Vector3d Kinematics::point_jacobian(const SurfacePoint& p, double* J3, const uint8_t* active) const {
    if (!derivatives_) fail(SSC_ERROR_INTERNAL, "point_jacobian after an update without derivatives");
    uint32_t shape_columns = K_;
    if (active)
        for (shape_columns = 0; shape_columns < K_ && active[shape_columns];) ++shape_columns;
    Vector3d out = Vector3d::Zero();
    for (int b = 0; b < 3; ++b)
        if (p.weight[b] != 0) out += p.weight[b] * vertex_jacobian(p.vertex[b], J3, p.weight[b], shape_columns, active);
    return scale_ * out + translation_;
}

Vector3d Kinematics::vertex_jacobian(uint32_t v, double* J3, double factor, uint32_t Ks, const uint8_t* active) const {
    const auto& skin = model_.data().skin;
    const uint32_t P = parameter_count();
    const Vector3d u = rest_vertex(v);
    const double f = factor * scale_;
    Vector3d blended = Vector3d::Zero();
    // Shape: sum_j w_j (S_j B_v + dc_j) = (sum_j w_j S_j) B_v + sum_j w_j dc_j: the blended rotation
    // multiplies the vertex's basis once, however many joints skin it.
    Matrix3d S = Matrix3d::Zero();
    for (int i = 0; i < 4; ++i) {
        const double w = skin.weights[4 * std::size_t(v) + i];
        if (w == 0) continue;
        const uint16_t j = skin.joints[4 * std::size_t(v) + i];
        S += (f * w) * skin_rot_[j];
        const double fw = f * w;
        for (std::size_t a = 0; a < 3; ++a) {
            // Plain pointers and size_t indices: the loops below vectorize only when the compiler
            // can see they are simple strides.
            double* row = J3 + a * P;
            const double* dc = dskin_.data() + (std::size_t(j) * 3 + a) * K_;
            for (std::size_t k = 0; k < Ks; ++k) row[k] += fw * dc[k];
        }
    }
    const int16_t* B = lin_.basis.data() + std::size_t(v) * 3 * K_;
    const double* step = lin_.step.data();
    for (std::size_t a = 0; a < 3; ++a) {
        double* row = J3 + a * P;
        const double s0 = S(Eigen::Index(a), 0), s1 = S(Eigen::Index(a), 1), s2 = S(Eigen::Index(a), 2);
        const int16_t *b0 = B, *b1 = B + K_, *b2 = B + 2 * std::size_t(K_);
        for (std::size_t k = 0; k < Ks; ++k) row[k] += (s0 * double(b0[k]) + s1 * double(b1[k]) + s2 * double(b2[k])) * step[k];
    }
    for (int i = 0; i < 4; ++i) {
        const double w = skin.weights[4 * std::size_t(v) + i];
        if (w == 0) continue;
        const uint16_t j = skin.joints[4 * std::size_t(v) + i];
        const Vector3d x = skin_rot_[j] * u + skin_trans_[j];
        blended += w * x;
        // Rotations of the joint and its ancestors: -w [x - q_k]_x, written entry by entry (a
        // Matrix3d temporary here went through the stack and stalled on store forwarding).
        double* row0 = J3;
        double* row1 = J3 + P;
        double* row2 = J3 + 2 * std::size_t(P);
        const double fw = f * w;
        for (uint32_t k : lin_.chains[j]) {
            const uint32_t off = rotation_offset(k);
            if (active && !active[off]) continue;
            const Vector3d r = fw * (x - posed_joint_[k]);
            row0[off + 1] += r.z(), row0[off + 2] -= r.y();
            row1[off] -= r.z(), row1[off + 2] += r.x();
            row2[off] += r.y(), row2[off + 1] -= r.x();
        }
    }
    const uint32_t t = translation_offset();
    for (uint32_t a = 0; a < 3; ++a) {
        J3[std::size_t(a) * P + t + a] += factor;
        J3[std::size_t(a) * P + scale_offset()] += factor * scale_ * blended[a];
    }
    return blended;
}

void Kinematics::apply(const double* delta, FitState& s) const {
    // The shape stays where the C API accepts it back (shape_range.hpp).
    for (uint32_t k = 0; k < K_; ++k) s.shape[k] = within_shape_range(s.shape[k] + delta[k]);
    for (uint32_t j = 0; j < J_; ++j) {
        const Vector3d w(delta + rotation_offset(j));
        if (w.squaredNorm() == 0) continue;
        s.pose[j] = (exp_rotation(pre_pose_[j].transpose() * w) * s.pose[j]).normalized();
    }
    s.translation += Vector3d(delta + translation_offset());
    s.scale *= std::exp(delta[scale_offset()]);
}

}  // namespace ssc::fitting
