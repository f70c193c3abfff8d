#include "anatomy/named_poses.hpp"

#include "anatomy/degrees.hpp"
#include "anatomy/joint_limits.hpp"
#include "common/error.hpp"

#include <cmath>

namespace ssc::anatomy {

namespace {

// Anatomical angles (JointAngles, named_poses.hpp) of the joints each pose moves.
struct Angle {
    const char* pose;
    JointAngles angles;
};

const Angle kAngles[] = {
    // The rest pose holds the upper arms 43° out from the body and the elbows 42° bent.
    {"t_pose", {"upperarm", 0, 0, -47}},  // arms horizontal
    {"t_pose", {"lowerarm", 40, 0, 0}},   // elbows straight
    {"arms_raised", {"upperarm", 0, 0, -132}},  // arms up beside the head (175° abduction)
    {"arms_raised", {"lowerarm", 40, 0, 0}},
    {"sitting", {"thigh", -90, 0, 0}},    // thighs horizontal
    {"sitting", {"calf", 83, 0, 0}},      // knees at a right angle (the rest pose bends them 7°)
    {"sitting", {"upperarm", -15, 0, 33}},  // arms lowered to the sides and a little forward
    {"sitting", {"lowerarm", -5, 0, 0}},    // forearms forward and down, towards the thighs
    // Crouching: hips and knees deeply bent, heels down, trunk leaning forward, arms forward.
    {"crouching", {"pelvis", 30, 0, 0, 'm'}},
    {"crouching", {"thigh", -120, 0, -10}},
    {"crouching", {"calf", 125, 0, 0}},
    {"crouching", {"foot", -20, 0, 0}},
    {"crouching", {"spine_01", 20, 0, 0, 'm'}},
    {"crouching", {"spine_02", 15, 0, 0, 'm'}},
    {"crouching", {"upperarm", -70, 0, 30}},
    {"crouching", {"lowerarm", -50, 0, 0}},
    // Kneeling upright: thighs vertical, knees bent a right angle, shins on the floor behind.
    {"kneeling", {"calf", 83, 0, 0}},
    {"kneeling", {"foot", 40, 0, 0}},
    {"kneeling", {"upperarm", -10, 0, 35}},
    // Bending forward from the hips, back rounded, arms hanging towards the floor. The pelvis (the
    // root, no limits) pitches forward by its flexion; the thighs flex as much, so the legs stay.
    {"bending_forward", {"pelvis", 55, 0, 0, 'm'}},
    {"bending_forward", {"thigh", -55, 0, 0}},
    {"bending_forward", {"spine_01", 28, 0, 0, 'm'}},
    {"bending_forward", {"spine_02", 28, 0, 0, 'm'}},
    {"bending_forward", {"spine_03", 20, 0, 0, 'm'}},
    {"bending_forward", {"neck_01", -20, 0, 0, 'm'}},
    {"bending_forward", {"upperarm", -95, 0, 20}},
    {"bending_forward", {"lowerarm", 30, 0, 0}},
    // Bending down to the toes, legs straight: folded deeper than bending_forward (161 degrees of
    // trunk against 131), the arms reaching down.
    {"touching_toes", {"pelvis", 80, 0, 0, 'm'}},
    {"touching_toes", {"thigh", -80, 0, 0}},
    {"touching_toes", {"spine_01", 28, 0, 0, 'm'}},
    {"touching_toes", {"spine_02", 28, 0, 0, 'm'}},
    {"touching_toes", {"spine_03", 25, 0, 0, 'm'}},
    {"touching_toes", {"upperarm", -95, -20, -15}},
    {"touching_toes", {"lowerarm", 40, 0, 0}},
    // Bent over with the arms raised past the head (reaching forward and up).
    {"bent_over_arms_raised", {"pelvis", 60, 0, 0, 'm'}},
    {"bent_over_arms_raised", {"thigh", -60, 0, 0}},
    {"bent_over_arms_raised", {"spine_01", 25, 0, 0, 'm'}},
    {"bent_over_arms_raised", {"spine_02", 25, 0, 0, 'm'}},
    {"bent_over_arms_raised", {"spine_03", 15, 0, 0, 'm'}},
    {"bent_over_arms_raised", {"upperarm", -160, -40, 10}},
    {"bent_over_arms_raised", {"lowerarm", 35, 0, 0}},
    // Lunge: the left leg forward, knee bent; the right leg back, knee bent towards the floor.
    {"lunge", {"thigh", -85, 0, 0, 'l'}},
    {"lunge", {"calf", 85, 0, 0, 'l'}},
    {"lunge", {"thigh", 25, 0, 0, 'r'}},
    {"lunge", {"calf", 75, 0, 0, 'r'}},
    {"lunge", {"foot", 40, 0, 0, 'r'}},
    {"lunge", {"upperarm", 0, 0, 30}},
    // Arms behind the back: upper arms back and in, elbows bent, hands meeting behind the waist.
    {"arms_behind_back", {"upperarm", 45, 40, 25}},
    {"arms_behind_back", {"lowerarm", -60, 0, 0}},
};

const std::vector<NamedPose> kPoses = {
    {"a_pose", "The rest pose: standing, arms about 45 degrees from the body, elbows and knees slightly bent."},
    {"t_pose", "Standing, arms straight out to the sides, horizontal."},
    {"sitting", "Seated: thighs horizontal, knees at a right angle, arms lowered with the forearms forward."},
    {"arms_raised", "Standing, arms straight up beside the head."},
    {"crouching", "Crouching: hips and knees deeply bent, trunk leaning forward, arms forward."},
    {"kneeling", "Kneeling upright on both knees, shins on the floor, arms at the sides."},
    {"bending_forward", "Bending forward from the hips with a rounded back, arms hanging towards the floor."},
    {"touching_toes", "Bending down to the toes with the legs straight, folded deeper than bending forward, arms reaching down."},
    {"bent_over_arms_raised", "Bent over from the hips with both arms raised forward past the head."},
    {"lunge", "Lunge: left leg forward with the knee bent, right leg back with the knee towards the floor."},
    {"arms_behind_back", "Standing with the upper arms back and the elbows bent, hands behind the waist."},
};

}  // namespace

const std::vector<NamedPose>& named_poses() { return kPoses; }

std::vector<float> named_pose(const Model& model, const std::string& name, const std::vector<JointLimit>* given) {
    bool known = false;
    for (const auto& p : kPoses) known |= name == p.name;
    if (!known) {
        std::string names;
        for (const auto& p : kPoses) names += std::string(names.empty() ? "" : ", ") + p.name;
        fail(SSC_ERROR_NOT_FOUND, "no named pose '" + name + "' (" + names + ")");
    }
    std::vector<JointAngles> angles;
    for (const Angle& a : kAngles)
        if (name == a.pose) angles.push_back(a.angles);
    return pose_from_angles(model, angles, given);
}

std::vector<float> pose_from_angles(const Model& model, const std::vector<JointAngles>& angles, const std::vector<JointLimit>* given) {
    const uint32_t J = model.joint_count();
    std::vector<float> q(4 * std::size_t(J), 0.f);
    for (uint32_t j = 0; j < J; ++j) q[4 * j + 3] = 1.f;
    const std::vector<JointLimit> made = given ? std::vector<JointLimit>() : joint_limits(model);
    const std::vector<JointLimit>& limits = given ? *given : made;
    for (const JointAngles& a : angles) {
        for (const char* side : {"_l", "_r", ""}) {
            const bool wanted = a.side == 'm' ? *side == 0 : *side != 0 && (a.side == 'b' || a.side == side[1]);
            if (!wanted) continue;
            const int64_t j = model.find_joint(std::string(a.joint) + side);
            if (j < 0) continue;
            Eigen::Quaterniond p;
            if (limits[std::size_t(j)].limited) {
                p = rotation_from_angles(limits[std::size_t(j)], kDeg * Vector3d(a.flexion, a.axial, a.abduction));
            } else {
                // A joint without limits (the pelvis): turned about the body's axes at rest (x its
                // left-right axis, y up, z forward), in the joint's rest frame W (rest orientations
                // chained from the root).
                const auto& sk = model.data().skeleton;
                Eigen::Quaterniond W = Eigen::Quaterniond::Identity();
                for (int64_t k = j; k >= 0; k = sk.parents[std::size_t(k)]) {
                    const float* r = &sk.rest_orientations[4 * std::size_t(k)];
                    W = Eigen::Quaterniond(r[3], r[0], r[1], r[2]).normalized() * W;
                }
                const Eigen::Quaterniond turn = Eigen::AngleAxisd(kDeg * a.axial, Vector3d::UnitY()) *
                                                Eigen::AngleAxisd(kDeg * a.flexion, Vector3d::UnitX()) *
                                                Eigen::AngleAxisd(kDeg * a.abduction, Vector3d::UnitZ());
                p = W.conjugate() * turn * W;
            }
            float* out = &q[4 * std::size_t(j)];
            out[0] = float(p.x()), out[1] = float(p.y()), out[2] = float(p.z()), out[3] = float(p.w());
        }
    }
    return q;
}

}  // namespace ssc::anatomy
