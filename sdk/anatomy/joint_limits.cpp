#include "anatomy/joint_limits.hpp"

#include "anatomy/degrees.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace ssc::anatomy {

namespace {

struct Range {
    const char* name;     // joint name without the side suffix
    char hinge;           // flexion axis: 'x' the body's left-right axis, 'a' across the arm (see
                          // joint_limits.hpp), 'z' the forward axis (the clavicle lies along x)
    double x_lo, x_hi;    // degrees, flexion axis x'
    double y_lo, y_hi;    // axial rotation about the bone
    double z_lo, z_hi;    // abduction axis z'
};

// Left-side conventions (right mirrored). Signs, from the rig's rest pose: +x' bends the trunk,
// neck and head forward and the knee, -x' swings the thigh and the upper arm forward and bends
// the elbow, +x' points the foot down; -z' abducts the thigh and raises the arm sideways.
// Rest-pose offsets are subtracted: the rest pose holds the upper arm 43° abducted, the elbow
// 42° and the knee 7° flexed.
const Range kRanges[] = {
    {"spine_01", 'x', -10, 30, -17, 17, -14, 14},
    {"spine_02", 'x', -10, 30, -17, 17, -14, 14},
    {"spine_03", 'x', -10, 30, -17, 17, -14, 14},
    {"neck_01", 'x', -28, 28, -35, 35, -26, 26},
    {"head", 'x', -25, 25, -30, 30, -22, 22},
    {"clavicle", 'z', -20, 20, -20, 20, -25, 25},
    {"upperarm", 'x', -185, 65, -95, 95, -140, 80},
    {"lowerarm", 'a', -113, 47, -90, 90, -15, 15},
    {"hand", 'a', -85, 75, -30, 30, -35, 35},
    {"thigh", 'x', -125, 35, -50, 50, -50, 35},
    {"calf", 'x', -12, 133, -20, 20, -8, 8},
    {"foot", 'x', -25, 55, -35, 35, -25, 25},
    {"ball", 'x', -40, 40, -10, 10, -10, 10},
};

}  // namespace

std::vector<format::JointLimit> compute_joint_limits(const format::Skeleton& sk) {
    const std::size_t J = sk.parents.size();
    std::vector<Matrix3d> W(J);  // rest world rotations
    for (std::size_t j = 0; j < J; ++j) {
        const float* q = &sk.rest_orientations[4 * j];
        const Matrix3d R = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
        W[j] = sk.parents[j] < 0 ? R : W[std::size_t(sk.parents[j])] * R;
    }
    auto find = [&](const std::string& name) -> int {
        for (std::size_t j = 0; j < J; ++j)
            if (sk.joint_names[j] == name) return int(j);
        return -1;
    };
    std::vector<format::JointLimit> out;
    for (const Range& r : kRanges) {
        for (const char* side : {"", "_l", "_r"}) {
            const int j = find(std::string(r.name) + side);
            if (j < 0) continue;
            const bool right = std::string(side) == "_r";
            const Vector3d bone = W[std::size_t(j)].col(1);
            Vector3d hinge = r.hinge == 'z' ? Vector3d::UnitZ() : Vector3d::UnitX();
            // The upper arm's own frame is built the same way from the body's x axis, which in the
            // rest pose lies across the arm; its forearm and hand hinge about that axis.
            if (r.hinge == 'a') {
                const int upper = find(std::string("upperarm") + side);
                if (upper >= 0) hinge = Vector3d::UnitZ().cross(W[std::size_t(upper)].col(1)).normalized();
            }
            Vector3d x = hinge - hinge.dot(bone) * bone;
            if (x.norm() < 0.2) continue;  // bone along the hinge: no frame (not in the default rig)
            x.normalize();
            Matrix3d A;
            A.col(0) = x;
            A.col(1) = bone;
            A.col(2) = x.cross(bone);
            Matrix3d mirror = Matrix3d::Identity();
            if (right) mirror(1, 1) = mirror(2, 2) = -1;
            const Matrix3d frame = mirror * A.transpose() * W[std::size_t(j)];
            format::JointLimit l;
            l.joint = uint32_t(j);
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) l.frame[3 * a + b] = float(frame(a, b));
            const double lo[3] = {r.x_lo, r.y_lo, r.z_lo}, hi[3] = {r.x_hi, r.y_hi, r.z_hi};
            for (int a = 0; a < 3; ++a) l.lower[a] = float(lo[a] * kDeg), l.upper[a] = float(hi[a] * kDeg);
            out.push_back(l);
        }
    }
    std::sort(out.begin(), out.end(), [](const format::JointLimit& a, const format::JointLimit& b) { return a.joint < b.joint; });
    return out;
}

std::vector<JointLimit> joint_limits(const Model& model) {
    std::vector<JointLimit> out(model.joint_count());
    for (const format::JointLimit& l : model.data().joint_limits) {
        JointLimit& o = out[l.joint];
        o.limited = true;
        for (int a = 0; a < 3; ++a) {
            for (int b = 0; b < 3; ++b) o.to_anatomical(a, b) = l.frame[3 * a + b];
            o.lo[a] = l.lower[a];
            o.hi[a] = l.upper[a];
        }
    }
    return out;
}

Vector3d anatomical_angles(const JointLimit& limit, const Eigen::Quaterniond& q) {
    const Eigen::AngleAxisd aa(q.normalized());
    return limit.to_anatomical * (aa.angle() * aa.axis());
}

Eigen::Quaterniond rotation_from_angles(const JointLimit& limit, const Vector3d& angles) {
    const Vector3d r = limit.to_anatomical.transpose() * angles;
    const double angle = r.norm();
    return angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, r / angle)) : Eigen::Quaterniond::Identity();
}

bool enforce_limit(const JointLimit& limit, Eigen::Quaterniond& q, bool clamp) {
    if (!limit.limited) return false;
    const Vector3d a = anatomical_angles(limit, q);
    const Vector3d inside = a.cwiseMax(limit.lo).cwiseMin(limit.hi);
    if ((a - inside).cwiseAbs().maxCoeff() <= 1e-5) return false;
    if (clamp) q = rotation_from_angles(limit, inside);
    return true;
}

}  // namespace ssc::anatomy
