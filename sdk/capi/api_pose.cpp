// Named poses and joint limits (anatomy/) through the C API.
#include "anatomy/hand_closure.hpp"
#include "anatomy/joint_limits.hpp"
#include "anatomy/named_poses.hpp"
#include "guard.hpp"
#include "handles.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace ssc;
using namespace ssc::capi;

extern "C" {

uint32_t ssc_named_pose_count(void) { return uint32_t(anatomy::named_poses().size()); }

ssc_status ssc_named_pose_get_info(uint32_t index, const char** out_name, const char** out_description) {
    return guarded(__func__, [&] {
        const auto& poses = anatomy::named_poses();
        SSC_REQUIRE_ARG(index < poses.size(), "named pose " + std::to_string(index) + " is out of range (count " +
                                                  std::to_string(poses.size()) + ")");
        if (out_name) *out_name = poses[index].name;
        if (out_description) *out_description = poses[index].description;
    });
}

ssc_status ssc_model_get_named_pose(const ssc_model* model, const char* name, float* rotations, uint32_t joint_capacity) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(name, "name");
        check_output(rotations, joint_capacity, model->model.joint_count(), 0, 16);
        const auto q = anatomy::named_pose(model->model, name, &model->limits);
        std::copy(q.begin(), q.end(), rotations);
    });
}

ssc_status ssc_model_close_hands(const ssc_model* model, float left_closure, float right_closure, float* rotations, uint32_t joint_count) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(rotations, "rotations");
        const uint32_t J = model->model.joint_count();
        SSC_REQUIRE_ARG(joint_count == J, "joint_count is " + std::to_string(joint_count) + "; the model has " + std::to_string(J) + " joints");
        for (const float c : {left_closure, right_closure})
            SSC_REQUIRE_ARG(c >= 0 && c <= 1, "a hand closure is in [0, 1] (0 open, 1 a fist), not " + std::to_string(c));
        for (const char side : {'l', 'r'})
            for (const auto& r : anatomy::hand_closure(model->model, side, side == 'l' ? left_closure : right_closure)) {
                float* q = rotations + 4 * std::size_t(r.joint);
                q[0] = float(r.rotation.x()), q[1] = float(r.rotation.y()), q[2] = float(r.rotation.z()), q[3] = float(r.rotation.w());
            }
    });
}

ssc_status ssc_model_get_joint_limit(const ssc_model* model, uint32_t joint, ssc_joint_limit* out) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(out, "out");
        SSC_REQUIRE_ARG(joint < model->model.joint_count(), "joint " + std::to_string(joint) + " is out of range (count " +
                                                                std::to_string(model->model.joint_count()) + ")");
        ssc_joint_limit l{};
        const anatomy::JointLimit& lim = model->limits[joint];
        if (lim.limited) {
            l.limited = 1;
            for (int a = 0; a < 3; ++a) {
                for (int b = 0; b < 3; ++b) l.frame[3 * a + b] = float(lim.to_anatomical(a, b));
                l.lower[a] = float(lim.lo[a]);
                l.upper[a] = float(lim.hi[a]);
            }
        }
        *out = l;
    });
}

ssc_status ssc_body_set_pose_limited(ssc_body* body, const float* rotations, uint32_t joint_count, const float* translation,
                                     ssc_limit_mode mode, uint32_t* out_violation_count) {
    return guarded(__func__, [&] {
        need(body, "body");
        need(rotations, "rotations");
        const int32_t m = enum_value(mode);
        SSC_REQUIRE_ARG(m == SSC_LIMITS_REJECT || m == SSC_LIMITS_CLAMP, "mode " + std::to_string(m) + " is not an ssc_limit_mode value");
        const uint32_t J = body->body.model().joint_count();
        std::vector<float> quats = checked_pose(body, SSC_ROTATION_QUATERNION, rotations, joint_count, translation);
        uint32_t violations = 0;
        std::string first;
        for (uint32_t j = 0; j < J; ++j) {
            float* q = &quats[4 * std::size_t(j)];
            Eigen::Quaterniond r(q[3], q[0], q[1], q[2]);
            const Eigen::Vector3d before = anatomy::anatomical_angles(body->model->limits[j], r);
            if (!anatomy::enforce_limit(body->model->limits[j], r, mode == SSC_LIMITS_CLAMP)) continue;
            if (violations++ == 0) {
                const auto& lim = body->model->limits[j];
                char text[200];
                std::snprintf(text, sizeof text, " (flexion %.1f, axial %.1f, abduction %.1f deg; range %.0f..%.0f, %.0f..%.0f, %.0f..%.0f)",
                              before[0] * 180 / M_PI, before[1] * 180 / M_PI, before[2] * 180 / M_PI, lim.lo[0] * 180 / M_PI,
                              lim.hi[0] * 180 / M_PI, lim.lo[1] * 180 / M_PI, lim.hi[1] * 180 / M_PI, lim.lo[2] * 180 / M_PI,
                              lim.hi[2] * 180 / M_PI);
                first = "joint '" + body->body.model().data().skeleton.joint_names[j] + "' is outside its limit" + text;
            }
            q[0] = float(r.x()), q[1] = float(r.y()), q[2] = float(r.z()), q[3] = float(r.w());
        }
        if (out_violation_count) *out_violation_count = violations;
        SSC_REQUIRE_ARG(mode == SSC_LIMITS_CLAMP || violations == 0, first + "; pose not set");
        body->body.set_pose(quats.data(), translation);
    });
}

}  // extern "C"
