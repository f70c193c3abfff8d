#include "anatomy/named_poses.hpp"

#include "anatomy/joint_limits.hpp"
#include "common/error.hpp"

#include <cmath>

namespace ssc::anatomy {

namespace {

constexpr double kDeg = M_PI / 180;

// Anatomical angles (degrees, relative to the rest pose; conventions of joint_limits.cpp: -x'
// swings the thigh and the upper arm forward and bends the elbow, +x' bends the knee, -z' raises
// the arm sideways) of the joints a pose moves, for both sides.
struct Angle {
    const char* pose;
    const char* joint;  // without the side suffix
    double flexion, axial, abduction;
};

const Angle kAngles[] = {
    // The rest pose holds the upper arms 43° out from the body and the elbows 42° bent.
    {"t_pose", "upperarm", 0, 0, -47},  // arms horizontal
    {"t_pose", "lowerarm", 40, 0, 0},   // elbows straight
    {"arms_raised", "upperarm", 0, 0, -132},  // arms up beside the head (175° abduction)
    {"arms_raised", "lowerarm", 40, 0, 0},
    {"sitting", "thigh", -90, 0, 0},    // thighs horizontal
    {"sitting", "calf", 83, 0, 0},      // knees at a right angle (the rest pose bends them 7°)
    {"sitting", "upperarm", -15, 0, 33},  // arms lowered to the sides and a little forward
    {"sitting", "lowerarm", -5, 0, 0},    // forearms forward and down, towards the thighs
};

const std::vector<NamedPose> kPoses = {
    {"a_pose", "The rest pose: standing, arms about 45 degrees from the body, elbows and knees slightly bent."},
    {"t_pose", "Standing, arms straight out to the sides, horizontal."},
    {"sitting", "Seated: thighs horizontal, knees at a right angle, arms lowered with the forearms forward."},
    {"arms_raised", "Standing, arms straight up beside the head."},
};

}  // namespace

const std::vector<NamedPose>& named_poses() { return kPoses; }

std::vector<float> named_pose(const Model& model, const std::string& name) {
    bool known = false;
    for (const auto& p : kPoses) known |= name == p.name;
    if (!known) fail(SSC_ERROR_NOT_FOUND, "no named pose '" + name + "' (a_pose, t_pose, sitting, arms_raised)");
    const uint32_t J = model.joint_count();
    std::vector<float> q(4 * std::size_t(J), 0.f);
    for (uint32_t j = 0; j < J; ++j) q[4 * j + 3] = 1.f;
    const auto limits = joint_limits(model);
    for (const Angle& a : kAngles) {
        if (name != a.pose) continue;
        for (const char* side : {"_l", "_r"}) {
            const int64_t j = model.find_joint(std::string(a.joint) + side);
            if (j < 0 || !limits[std::size_t(j)].limited) continue;
            const Eigen::Quaterniond p = rotation_from_angles(limits[std::size_t(j)], kDeg * Vector3d(a.flexion, a.axial, a.abduction));
            float* out = &q[4 * std::size_t(j)];
            out[0] = float(p.x()), out[1] = float(p.y()), out[2] = float(p.z()), out[3] = float(p.w());
        }
    }
    return q;
}

}  // namespace ssc::anatomy
