#include "anatomy/hand_closure.hpp"

#include "anatomy/degrees.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace ssc::anatomy {

namespace {

struct Finger {
    const char* name;
    double full[3];  // degrees at closure 1: segments 01, 02, 03
};

const Finger kFingers[] = {
    {"index", {80, 95, 65}}, {"middle", {80, 95, 65}}, {"ring", {80, 95, 65}}, {"pinky", {80, 95, 65}}, {"thumb", {15, 30, 40}},
};

}  // namespace

std::vector<JointRotation> hand_closure(const Model& model, char side, double closure) {
    const std::string suffix = side == 'r' ? "_r" : "_l";
    const int64_t hand = model.find_joint("hand" + suffix), index = model.find_joint("index_01" + suffix),
                  pinky = model.find_joint("pinky_01" + suffix);
    if (hand < 0 || index < 0 || pinky < 0) return {};
    const auto& sk = model.data().skeleton;
    const float* jm = model.joint_mean();
    auto position = [&](int64_t j) { return Vector3d(jm[3 * j], jm[3 * j + 1], jm[3 * j + 2]); };
    // Rest world rotation of a joint: the rest orientations chained from the root.
    auto rest_world = [&](int64_t j) {
        Eigen::Quaterniond w = Eigen::Quaterniond::Identity();
        for (int64_t k = j; k >= 0; k = sk.parents[std::size_t(k)]) {
            const float* r = &sk.rest_orientations[4 * std::size_t(k)];
            w = Eigen::Quaterniond(r[3], r[0], r[1], r[2]).normalized() * w;
        }
        return w;
    };
    const Vector3d to_index = position(index) - position(hand), to_pinky = position(pinky) - position(hand);
    // The palm faces the side where, looking along the fingers, the index lies on the thumb's side:
    // the cross product's order flips with the side.
    Vector3d palm = side == 'r' ? to_index.cross(to_pinky) : to_pinky.cross(to_index);
    if (palm.norm() < 1e-9) return {};
    palm.normalize();
    const double c = std::clamp(closure, 0.0, 1.0);
    std::vector<JointRotation> out;
    for (const Finger& f : kFingers)
        for (int segment = 0; segment < 3; ++segment) {
            const int64_t j = model.find_joint(std::string(f.name) + "_0" + std::to_string(segment + 1) + suffix);
            if (j < 0) continue;
            const Eigen::Quaterniond w = rest_world(j);
            const Vector3d bone = w * Vector3d::UnitY();  // the rig's bones run along their frame's +Y
            Vector3d axis = bone.cross(palm);
            if (axis.norm() < 1e-6) continue;
            axis.normalize();
            // A rotation about the world axis, expressed in the joint's rest frame.
            const Vector3d local = w.conjugate() * axis;
            out.push_back({uint32_t(j), Eigen::Quaterniond(Eigen::AngleAxisd(c * f.full[segment] * kDeg, local))});
        }
    return out;
}

}  // namespace ssc::anatomy
