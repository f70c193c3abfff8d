#include "fitting/priors.hpp"

#include "anatomy/hand_closure.hpp"

#include <cmath>

namespace ssc::fitting {

namespace {

Matrix3d skew(const Vector3d& a) {
    Matrix3d m;
    m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
    return m;
}

// Inverse of the left Jacobian of SO(3): d log(exp(d) exp(r)) / d d at d = 0.
Matrix3d inverse_left_jacobian(const Vector3d& r) {
    const double t = r.norm();
    const Matrix3d K = skew(r);
    if (t < 1e-6) return Matrix3d::Identity() - 0.5 * K + K * K / 12.0;
    return Matrix3d::Identity() - 0.5 * K + (1.0 / (t * t) - (1.0 + std::cos(t)) / (2.0 * t * std::sin(t))) * K * K;
}

// Adds J^T J (upper triangle) and J^T e of a 3-row term on a joint's three rotation columns.
void add_rotation_term(const Matrix3d& J, const Vector3d& e, uint32_t c0, ArrowSystem& H, Eigen::VectorXd& g) {
    const Matrix3d JtJ = J.transpose() * J;
    const Vector3d Jte = J.transpose() * e;
    for (int a = 0; a < 3; ++a) {
        g[c0 + a] += Jte[a];
        for (int b = a; b < 3; ++b) H.add(c0 + a, c0 + b, JtJ(a, b));
    }
}

}  // namespace

Vector3d log_rotation(const Eigen::Quaterniond& q) {
    const Eigen::AngleAxisd aa(q);
    return aa.angle() * aa.axis();
}

PosePrior::PosePrior(const LinearModel& lin, double weight, bool limits) : weight_(weight) {
    for (const anatomy::JointRole& role : lin.roles) {
        joint_sigma_.push_back(role.rotation_sigma);
        coarse_joint_.push_back(role.coarse);
    }
    // The fingers' rotation vectors at closure 1: at closure c the prior's centre is c times
    // that (each finger segment turns about a fixed axis).
    closed_fingers_.assign(lin.J, Vector3d::Zero());
    hand_of_joint_.assign(lin.J, -1);
    for (int hand = 0; hand < 2; ++hand)
        for (const auto& r : anatomy::hand_closure(lin.model, hand == 0 ? 'l' : 'r', 1.0)) {
            closed_fingers_[r.joint] = log_rotation(r.rotation);
            hand_of_joint_[r.joint] = int8_t(hand);
        }
    if (limits) limits_ = lin.limits;
}

double PosePrior::evaluate(const Kinematics& kin, const FitState& state, uint32_t frame_offset, ArrowSystem* H,
                           Eigen::VectorXd* g) const {
    double cost = 0;
    const uint32_t J = uint32_t(joint_sigma_.size());
    // Each joint's local rotation vector over its sigma (not the root: free).
    for (uint32_t j = 1; j < J; ++j) {
        const double s = std::sqrt(weight_) / joint_sigma_[j];
        if (s == 0) continue;
        const Vector3d r = log_rotation(state.pose[j]);
        // Centred on the rest pose, the fingers on their hand's closure.
        const Vector3d centre = hand_of_joint_[j] < 0 ? Vector3d(Vector3d::Zero())
                                                      : Vector3d(state.hand_closure[hand_of_joint_[j]] * closed_fingers_[j]);
        cost += 0.5 * s * s * (r - centre).squaredNorm();
        if (!H) continue;
        const Matrix3d Jr = s * inverse_left_jacobian(r) * kin.local_from_world(j);
        add_rotation_term(Jr, s * (r - centre), frame_offset + kin.rotation_offset(j), *H, *g);
    }
    // Joint limits: a quadratic wall per anatomical component beyond its range.
    for (uint32_t j = 1; j < J && !limits_.empty(); ++j) {
        const anatomy::JointLimit& lim = limits_[j];
        if (!lim.limited) continue;
        const Vector3d r = log_rotation(state.pose[j]);
        const Vector3d c = lim.to_anatomical * r;
        Vector3d e = Vector3d::Zero();
        for (int a = 0; a < 3; ++a) {
            if (c[a] > lim.hi[a]) e[a] = (c[a] - lim.hi[a]) / kLimitSigma;
            else if (c[a] < lim.lo[a]) e[a] = (c[a] - lim.lo[a]) / kLimitSigma;
        }
        if (e.isZero()) continue;
        cost += 0.5 * e.squaredNorm();
        if (!H) continue;
        // Rows of the active components only: d c / d w = M J_l^-1(r) A^T, over the sigma.
        Matrix3d Jc = lim.to_anatomical * inverse_left_jacobian(r) * kin.local_from_world(j) / kLimitSigma;
        for (int a = 0; a < 3; ++a)
            if (e[a] == 0) Jc.row(a).setZero();
        add_rotation_term(Jc, e, frame_offset + kin.rotation_offset(j), *H, *g);
    }
    return cost;
}

void add_shape_prior(const std::vector<double>& shape, double weight, uint32_t whole_body, double segment_weight, double& cost,
                     ArrowSystem* H, Eigen::VectorXd* g) {
    for (uint32_t k = 0; k < shape.size(); ++k) {
        const double w = k < whole_body ? weight : weight * segment_weight;
        cost += 0.5 * w * shape[k] * shape[k];
        if (!H) continue;
        H->add(k, k, w);
        (*g)[k] += w * shape[k];
    }
}

}  // namespace ssc::fitting
