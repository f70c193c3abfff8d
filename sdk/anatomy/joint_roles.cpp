#include "anatomy/joint_roles.hpp"

namespace ssc::anatomy {

namespace {

constexpr double kLoose = 0.6, kWrist = 0.3, kTight = 0.15;  // rotation sigmas, radians

bool contains(const std::string& s, const char* part) { return s.find(part) != std::string::npos; }
bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

bool is_finger(const std::string& name) {
    for (const char* f : {"thumb", "index", "middle", "ring", "pinky"})
        if (contains(name, f)) return true;
    return false;
}

// The rig's side suffixes.
Side side_of(const std::string& name) {
    const std::size_t n = name.size();
    if (n >= 2 && name.compare(n - 2, 2, "_l") == 0) return Side::Left;
    if (n >= 2 && name.compare(n - 2, 2, "_r") == 0) return Side::Right;
    return Side::Centre;
}

JointRole role_of(const std::string& name) {
    JointRole r;
    r.side = side_of(name);
    const std::string base = r.side == Side::Centre ? name : name.substr(0, name.size() - 2);
    auto set = [&](BodyPart part, double sigma, bool coarse) {
        r.part = part, r.rotation_sigma = sigma, r.coarse = coarse;
        return r;
    };
    if (contains(name, "head") || contains(name, "neck")) return set(BodyPart::Head, kLoose, true);
    if (is_finger(name)) return set(BodyPart::Hand, kTight, false);
    // The wrist ("hand_l") is tighter and left to the fine stage; other hand joints are loose.
    if (contains(name, "hand")) return set(BodyPart::Hand, starts_with(name, "hand") ? kWrist : kLoose, !starts_with(name, "hand"));
    if (contains(name, "upperarm") || contains(name, "lowerarm")) {
        // The limb search poses the shoulder and elbow themselves (not twist joints).
        if (r.side != Side::Centre && (base == "upperarm" || base == "lowerarm"))
            r.limb_joint = base == "upperarm" ? LimbJoint::Upper : LimbJoint::Middle;
        return set(BodyPart::Arm, kLoose, true);
    }
    if (contains(name, "thigh") || contains(name, "calf")) {
        if (r.side != Side::Centre && (base == "thigh" || base == "calf"))
            r.limb_joint = base == "thigh" ? LimbJoint::Upper : LimbJoint::Middle;
        return set(BodyPart::Leg, kLoose, true);
    }
    if (contains(name, "ball")) return set(BodyPart::Foot, kTight, false);
    if (contains(name, "foot")) return set(BodyPart::Foot, kLoose, true);
    return set(BodyPart::Torso, kLoose, true);
}

}  // namespace

std::vector<format::JointRole> compute_joint_roles(const format::Skeleton& skeleton) {
    std::vector<format::JointRole> out;
    for (const std::string& name : skeleton.joint_names) {
        const JointRole r = role_of(name);
        format::JointRole f;
        f.part = uint8_t(r.part);
        f.side = uint8_t(r.side);
        f.rotation_sigma = r.rotation_sigma;
        f.coarse = r.coarse;
        f.limb_joint = uint8_t(r.limb_joint);
        out.push_back(f);
    }
    return out;
}

std::vector<JointRole> joint_roles(const Model& model) {
    const format::ModelData& d = model.data();
    const std::vector<format::JointRole> stored = d.joint_roles.empty() ? compute_joint_roles(d.skeleton) : d.joint_roles;
    std::vector<JointRole> out;
    for (const format::JointRole& f : stored) {
        JointRole r;
        r.part = BodyPart(f.part);
        r.side = Side(f.side);
        r.rotation_sigma = f.rotation_sigma;
        r.coarse = f.coarse;
        r.limb_joint = LimbJoint(f.limb_joint);
        out.push_back(r);
    }
    return out;
}

int64_t find_limb_joint(const std::vector<JointRole>& roles, BodyPart part, Side side, LimbJoint which) {
    for (std::size_t j = 0; j < roles.size(); ++j)
        if (roles[j].part == part && roles[j].side == side && roles[j].limb_joint == which) return int64_t(j);
    return -1;
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
