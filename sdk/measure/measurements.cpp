// The measurement definitions and how each is taken. Girths are tape girths (girth.hpp): the
// convex hull of the body's section in the defined plane, restricted to the body part measured.
//
// Sources: ISO 8559-1:2017 (size designation of clothes: anthropometric definitions for body
// measurement) and ISO 7250-1:2017 (basic human body measurements for technological design) for
// the definitions named below; the WHO waist protocol (Waist circumference and waist-hip ratio:
// report of a WHO expert consultation, Geneva 2008). The clause numbers of the ISO documents could
// not be checked here, so each definition is described in words instead.
#include "measure/measurements.hpp"

#include "common/error.hpp"
#include "measure/girth.hpp"
#include "synthesis/kernels.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ssc::measure {

using Eigen::Vector3d;

namespace {

enum Index {
    kStature, kChest, kUnderbust, kWaist, kHip, kNeck, kThigh, kCalf, kUpperArm, kWrist,
    kInseam, kArmLength, kShoulderBreadth, kSurfaceArea, kVolume, kMass, kCount
};

const std::vector<Definition> kDefinitions = {
    {"stature", Unit::Metre,
     "Body height: vertical distance from the floor (the lowest point of the soles) to the highest point of the head, "
     "standing (ISO 7250-1 body height)."},
    {"chest_girth", Unit::Metre,
     "Bust/chest girth: horizontal girth of the trunk at the height of the bust points (thelion), arms excluded, the "
     "tape passing over the shoulder blades and spanning the hollow between the breasts (ISO 8559-1 bust girth)."},
    {"underbust_girth", Unit::Metre,
     "Horizontal girth of the trunk just below the breasts (ISO 8559-1 underbust girth), at the inframammary fold: "
     "the concave corner of the front profile 3 to 12 cm below the bust points."},
    {"waist_girth", Unit::Metre,
     "Horizontal girth of the trunk midway between the lowest rib (10th rib) and the top of the iliac crest: the WHO "
     "protocol (WHO expert consultation, 2008); ISO 8559-1 places the natural waist between the same bones."},
    {"hip_girth", Unit::Metre,
     "Horizontal girth at the level of the greatest protrusion of the buttocks, around buttocks and both thighs "
     "(ISO 8559-1 hip girth); the level is searched between the crotch and the iliac crest."},
    {"neck_girth", Unit::Metre,
     "Girth of the neck perpendicular to its axis, midway between the base of the neck and the skull, about the "
     "laryngeal prominence (ISO 8559-1 neck girth: just below the Adam's apple)."},
    {"thigh_girth", Unit::Metre,
     "Horizontal girth of the right thigh at its highest point, just below the gluteal fold (ISO 8559-1 thigh girth): "
     "3 cm below the crotch."},
    {"calf_girth", Unit::Metre,
     "Maximum horizontal girth of the right calf, searched between the knee crease and the ankle (ISO 8559-1 calf "
     "girth)."},
    {"upper_arm_girth", Unit::Metre,
     "Girth of the right upper arm perpendicular to its axis, midway between the acromion and the olecranon "
     "(ISO 8559-1 upper arm girth)."},
    {"wrist_girth", Unit::Metre,
     "Girth of the right wrist perpendicular to the forearm, over the styloid processes of radius and ulna "
     "(ISO 8559-1 wrist girth)."},
    {"inseam", Unit::Metre,
     "Crotch height: vertical distance from the floor to the crotch (ISO 7250-1 crotch height; a tailor's inside leg "
     "length)."},
    {"arm_length", Unit::Metre,
     "Right arm length from the acromion over the elbow (olecranon) to the wrist (ulnar styloid), the arm slightly "
     "bent as in the rest pose (ISO 8559-1 arm length)."},
    {"shoulder_breadth", Unit::Metre,
     "Biacromial breadth: straight distance between the two acromia (ISO 7250-1 biacromial breadth)."},
    {"surface_area", Unit::SquareMetre, "Area of the body surface: the sum of its triangles."},
    {"volume", Unit::CubicMetre, "Volume enclosed by the body surface (divergence theorem over its triangles)."},
    {"mass", Unit::Kilogram, "Estimated mass: volume times an assumed whole-body density of 1010 kg/m^3."},
};

// The landmarks the definitions use, in Measurer::landmark_ order.
enum Needed {
    kThelionR, kThelionL, kRibR, kRibL, kCrestR, kCrestL, kCrotch, kAcromionR, kAcromionL, kOlecranonR,
    kUlnarR, kRadialR, kKneeCreaseR, kMalleolusR, kNeededCount
};
const char* const kNeededNames[kNeededCount] = {
    "Rt. Thelion/Bustpoint", "Lt. Thelion/Bustpoint", "Rt. 10th Rib", "Lt. 10th Rib", "Rt. Iliocristale",
    "Lt. Iliocristale", "Crotch", "Rt. Acromion", "Lt. Acromion", "Rt. Olecranon", "Rt. Ulnar Styloid",
    "Rt. Radial Styloid", "Rt. Knee Crease", "Rt. Lateral Malleolus"};

Vector3d at(const float* p, std::size_t i) { return Vector3d(p[3 * i], p[3 * i + 1], p[3 * i + 2]); }

// Searched levels (hip, calf) are cut every 5 mm, but never more than kMaxLevels of them: a search
// range longer than a real body's gets a wider step, so the work stays bounded by the mesh.
constexpr double kLevelStep = 0.005;
constexpr int kMaxLevels = 200;

struct Levels {
    double step;
    int count;
};
Levels search_levels(double range) {
    if (!(range >= 0)) return {kLevelStep, 0};  // an empty range: no level to search
    const double step = std::max(kLevelStep, range / (kMaxLevels - 1));
    return {step, std::min(kMaxLevels, int(std::floor(range / step)) + 1)};
}

// Bodies the definitions can be taken on: finite, and no larger than any person (a shape far
// outside the population, or a model in other units, is refused rather than measured).
void check_measurable(const float* xyz, uint32_t V, const float* joints, uint32_t J) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (uint32_t v = 0; v < V; ++v) {
        const Vector3d p = at(xyz, v);
        SSC_REQUIRE_ARG(p.allFinite(), "the body's vertex " + std::to_string(v) + " is not finite");
        lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    }
    for (uint32_t j = 0; j < 3 * J; ++j) SSC_REQUIRE_ARG(std::isfinite(joints[j]), "the body's joints are not finite");
    const double extent = V ? (hi - lo).maxCoeff() : 0;
    if (extent > kMaxBodyExtent) {
        char text[64];
        std::snprintf(text, sizeof text, "%.4g m", extent);
        fail(SSC_ERROR_INVALID_ARGUMENT, std::string("the body spans ") + text + "; measurements are defined for bodies within " +
                                             std::to_string(int(kMaxBodyExtent)) +
                                             " m (its shape is far outside the model's population)");
    }
}

}  // namespace

const std::vector<Definition>& definitions() {
    static_assert(kCount == 16, "one definition per index");
    return kDefinitions;
}

int find_measurement(const std::string& name) {
    for (std::size_t i = 0; i < kDefinitions.size(); ++i)
        if (name == kDefinitions[i].name) return int(i);
    return -1;
}

Vector3d landmark_position(const format::ModelData& d, uint32_t l, const float* xyz) {
    const auto& lm = d.landmarks[l];
    if (lm.vertex != format::kNone) return at(xyz, lm.vertex);
    Vector3d p = Vector3d::Zero();
    for (int i = 0; i < 3; ++i) p += double(lm.barycentric[i]) * at(xyz, d.mesh.triangles[3 * std::size_t(lm.triangle) + i]);
    return p;
}

Measurer::Measurer(const Model& model) : model_(model) {
    const auto& d = model.data();
    for (const char* name : kNeededNames) {
        const int64_t l = model.find_landmark(name);
        if (l < 0) fail(SSC_ERROR_NOT_FOUND, std::string("measurements need the landmark '") + name + "', which this model lacks");
        landmark_.push_back(uint32_t(l));
    }
    auto joint = [&](const char* name) {
        const int64_t j = model.find_joint(name);
        if (j < 0) fail(SSC_ERROR_NOT_FOUND, std::string("measurements need the joint '") + name + "', which this model lacks");
        return uint32_t(j);
    };
    upperarm_ = joint("upperarm_r"), lowerarm_ = joint("lowerarm_r"), hand_ = joint("hand_r");
    neck_ = joint("neck_01"), head_ = joint("head");
    const uint32_t V = model.vertex_count();
    auto set = [&](const char* name) {
        std::vector<uint8_t> in(V, 0);
        for (const auto& s : d.vertex_sets)
            if (s.name == name) {
                for (uint32_t v : s.vertices) in[v] = 1;
                return in;
            }
        fail(SSC_ERROR_NOT_FOUND, std::string("measurements need the vertex set '") + name + "', which this model lacks");
    };
    const auto torso = set("torso"), head = set("head"), arms = set("arms"), hands = set("hands"), legs = set("legs"),
               feet = set("feet");
    // The body's right side: the sign of x at the right acromion of the mean shape.
    const double right = model.landmark_rest()[3 * std::size_t(landmark_[kAcromionR])] < 0 ? -1.0 : 1.0;
    std::vector<uint8_t> trunk_legs(V), right_leg(V), right_arm(V), neck_region(V);
    for (uint32_t v = 0; v < V; ++v) {
        const bool on_right = right * d.shape.mean[3 * std::size_t(v)] > 0;
        trunk_legs[v] = torso[v] || legs[v];
        right_leg[v] = (legs[v] || feet[v]) && on_right;
        right_arm[v] = (arms[v] || hands[v]) && on_right;
        neck_region[v] = head[v] || torso[v];
    }
    const uint32_t* tris = d.mesh.triangles.data();
    const std::size_t T = d.mesh.triangles.size() / 3;
    torso_ = mesh_edges(tris, T, torso);
    trunk_legs_ = mesh_edges(tris, T, trunk_legs);
    right_leg_ = mesh_edges(tris, T, right_leg);
    right_arm_ = mesh_edges(tris, T, right_arm);
    neck_region_ = mesh_edges(tris, T, neck_region);
}

std::vector<double> Measurer::measure(const float* xyz, const float* joints, std::vector<Path>* paths,
                                      const std::vector<bool>* only) const {
    if (only && only->size() != std::size_t(kCount)) fail(SSC_ERROR_INTERNAL, "measure: 'only' needs one flag per measurement");
    auto want = [&](int m) { return !only || (*only)[std::size_t(m)]; };
    const auto& d = model_.data();
    const uint32_t V = model_.vertex_count();
    const uint32_t* tris = d.mesh.triangles.data();
    const std::size_t T = d.mesh.triangles.size() / 3;
    check_measurable(xyz, V, joints, model_.joint_count());
    std::vector<double> out(kCount, 0.0);
    std::vector<Path> path(kCount);
    Vector3d lm[kNeededCount];
    for (int i = 0; i < kNeededCount; ++i) lm[i] = landmark_position(d, landmark_[std::size_t(i)], xyz);

    // Tape girth in a plane; its path for pictures.
    auto girth = [&](int index, const Plane& plane, const std::vector<uint32_t>& edges, double radius = 1e30) {
        std::vector<Vector3d> hull;
        const double g = tape_girth(plane_section(xyz, edges, plane, radius), plane, &hull);
        path[std::size_t(index)] = {hull, true};
        out[std::size_t(index)] = g;
    };
    auto horizontal = horizontal_plane;

    std::size_t top = 0, bottom = 0;
    for (uint32_t v = 1; v < V; ++v) {
        if (xyz[3 * v + 1] > xyz[3 * top + 1]) top = v;
        if (xyz[3 * v + 1] < xyz[3 * bottom + 1]) bottom = v;
    }
    const double floor = xyz[3 * bottom + 1];
    const Vector3d crown = at(xyz, top);
    out[kStature] = crown.y() - floor;
    path[kStature] = {{crown, Vector3d(crown.x(), floor, crown.z())}, false};

    const double bust = 0.5 * (lm[kThelionR].y() + lm[kThelionL].y());
    if (want(kChest)) girth(kChest, horizontal(bust), torso_);

    // Underbust: the inframammary fold is the concave corner of the front profile below the bust
    // points, where the breast's underside meets the chest wall: the largest second difference of
    // the profile's forward reach (a flat chest has none to speak of and gets a level just below).
    const double step = kLevelStep;
    if (want(kUnderbust)) {
        std::vector<double> front;
        for (const auto& section : horizontal_sections(xyz, torso_, bust, step, 31)) {  // bust - 0 .. bust - 15 cm
            double reach = -1e30;
            for (const Vector3d& p : section)
                if (std::abs(p.x() - lm[kThelionR].x()) < 0.03 || std::abs(p.x() - lm[kThelionL].x()) < 0.03) reach = std::max(reach, p.z());
            front.push_back(reach);
        }
        double fold = bust - 0.04, corner = -1e30;
        for (int i = 6; i <= 24; ++i) {  // 3 to 12 cm below, the profile 1 cm above and below
            if (front[std::size_t(i - 2)] < -1e29 || front[std::size_t(i)] < -1e29 || front[std::size_t(i + 2)] < -1e29) continue;
            const double bend = front[std::size_t(i - 2)] + front[std::size_t(i + 2)] - 2 * front[std::size_t(i)];
            if (bend > corner) corner = bend, fold = bust - i * step;
        }
        girth(kUnderbust, horizontal(fold), torso_);
    }

    const double rib = 0.5 * (lm[kRibR].y() + lm[kRibL].y()), crest = 0.5 * (lm[kCrestR].y() + lm[kCrestL].y());
    if (want(kWaist)) girth(kWaist, horizontal(0.5 * (rib + crest)), torso_);

    // Hip: the level where the buttocks reach farthest back (the body faces +z).
    if (want(kHip)) {
        double hip = 0.5 * (lm[kCrotch].y() + crest), back = 1e30;
        const Levels levels = search_levels(crest - lm[kCrotch].y() - 0.02);  // crest down to crotch + 2 cm
        const auto hip_sections = horizontal_sections(xyz, trunk_legs_, crest, levels.step, levels.count);
        for (int i = levels.count - 1; i >= 0; --i)  // upwards, so ties keep the lowest level
            for (const Vector3d& p : hip_sections[std::size_t(i)])
                if (p.z() < back) back = p.z(), hip = crest - i * levels.step;
        girth(kHip, horizontal(hip), trunk_legs_);
    }

    const Vector3d neck = at(joints, neck_), head = at(joints, head_);
    if (want(kNeck)) girth(kNeck, Plane{0.5 * (neck + head), (head - neck).normalized()}, neck_region_, 0.10);

    if (want(kThigh)) girth(kThigh, horizontal(lm[kCrotch].y() - 0.03), right_leg_);

    if (want(kCalf)) {
        double calf = 0;
        std::vector<Vector3d> calf_path;
        const double knee = lm[kKneeCreaseR].y();
        const Levels levels = search_levels(knee - lm[kMalleolusR].y());
        const auto calf_sections = horizontal_sections(xyz, right_leg_, knee, levels.step, levels.count);
        for (int i = 0; i < levels.count; ++i) {
            std::vector<Vector3d> hull;
            const double g = tape_girth(calf_sections[std::size_t(i)], horizontal(knee - i * levels.step), &hull);
            if (g > calf) calf = g, calf_path = hull;
        }
        out[kCalf] = calf;
        path[kCalf] = {calf_path, true};
    }

    const Vector3d shoulder = at(joints, upperarm_), elbow = at(joints, lowerarm_), wrist = at(joints, hand_);
    if (want(kUpperArm)) girth(kUpperArm, Plane{0.5 * (lm[kAcromionR] + lm[kOlecranonR]), (elbow - shoulder).normalized()}, right_arm_, 0.10);
    if (want(kWrist)) girth(kWrist, Plane{0.5 * (lm[kRadialR] + lm[kUlnarR]), (wrist - elbow).normalized()}, right_arm_, 0.06);

    out[kInseam] = lm[kCrotch].y() - floor;
    path[kInseam] = {{lm[kCrotch], Vector3d(lm[kCrotch].x(), floor, lm[kCrotch].z())}, false};
    out[kArmLength] = (lm[kAcromionR] - lm[kOlecranonR]).norm() + (lm[kOlecranonR] - lm[kUlnarR]).norm();
    path[kArmLength] = {{lm[kAcromionR], lm[kOlecranonR], lm[kUlnarR]}, false};
    out[kShoulderBreadth] = (lm[kAcromionR] - lm[kAcromionL]).norm();
    path[kShoulderBreadth] = {{lm[kAcromionR], lm[kAcromionL]}, false};

    // Area, and volume from the centroid (exact for a closed surface; the reference point keeps the
    // error of the small openings at eyes and mouth small).
    if (want(kSurfaceArea) || want(kVolume) || want(kMass)) {
        Vector3d centre = Vector3d::Zero();
        for (uint32_t v = 0; v < V; ++v) centre += at(xyz, v);
        centre /= double(V);
        double area = 0, six_volume = 0;
        for (std::size_t t = 0; t < T; ++t) {
            const Vector3d a = at(xyz, tris[3 * t]) - centre, b = at(xyz, tris[3 * t + 1]) - centre, c = at(xyz, tris[3 * t + 2]) - centre;
            area += 0.5 * (b - a).cross(c - a).norm();
            six_volume += a.dot(b.cross(c));
        }
        out[kSurfaceArea] = area;
        out[kVolume] = std::abs(six_volume) / 6.0;
        out[kMass] = out[kVolume] * kBodyDensity;
    }
    if (paths) *paths = std::move(path);
    return out;
}

std::vector<double> Measurer::measure(Body& body, std::vector<Path>* paths, const std::vector<bool>* only) const {
    const uint32_t V = model_.vertex_count();
    std::vector<float> xyz(3 * std::size_t(V));
    kernels::planar_to_xyz(body.rest_planar(), V, xyz.data(), 12);
    return measure(xyz.data(), body.rest_joints(), paths, only);
}

}  // namespace ssc::measure
