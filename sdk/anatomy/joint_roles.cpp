#include "anatomy/joint_roles.hpp"

namespace ssc::anatomy {

namespace {

constexpr double kLoose = 0.6, kWrist = 0.3, kTight = 0.15;  // rotation sigmas, radians

bool contains(const std::string& s, const char* part) { return s.find(part) != std::string::npos; }

bool is_finger(const std::string& name) {
    for (const char* f : {"thumb", "index", "middle", "ring", "pinky"})
        if (contains(name, f)) return true;
    return false;
}

}  // namespace

JointRole joint_role(const std::string& name) {
    if (contains(name, "head") || contains(name, "neck")) return {BodyPart::Head, kLoose, true};
    if (is_finger(name)) return {BodyPart::Hand, kTight, false};
    if (contains(name, "hand")) return {BodyPart::Hand, name.rfind("hand", 0) == 0 ? kWrist : kLoose, name.rfind("hand", 0) != 0};
    if (contains(name, "upperarm") || contains(name, "lowerarm")) return {BodyPart::Arm, kLoose, true};
    if (contains(name, "thigh") || contains(name, "calf")) return {BodyPart::Leg, kLoose, true};
    if (contains(name, "ball")) return {BodyPart::Foot, kTight, false};
    if (contains(name, "foot")) return {BodyPart::Foot, kLoose, true};
    return {BodyPart::Torso, kLoose, true};
}

const char* part_name(BodyPart part) {
    switch (part) {
        case BodyPart::Head: return "head";
        case BodyPart::Arm: return "arms";
        case BodyPart::Hand: return "hands";
        case BodyPart::Leg: return "legs";
        case BodyPart::Foot: return "feet";
        default: return "torso";
    }
}

}  // namespace ssc::anatomy
