#include "landmarks.hpp"

#include "common/error.hpp"
#include "skeleton_fit.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <limits>
#include <utility>

namespace ssc::training {
namespace {

using Eigen::Vector3d;

struct Hit {
    uint32_t triangle = format::kNone;
    double u = 0, v = 0, t = 0;  // barycentric of corners 1 and 2, ray distance
};

class Placer {
public:
    explicit Placer(const LandmarkTemplate& t) : t_(t) {}

    Vector3d vertex(uint32_t v) const { return Vector3d(t_.xyz[3 * v], t_.xyz[3 * v + 1], t_.xyz[3 * v + 2]); }
    Vector3d joint(const std::string& name) const {
        const auto it = t_.joints.find(name);
        if (it == t_.joints.end()) fail(SSC_ERROR_INTERNAL, "landmark rules need joint '" + name + "'");
        return Vector3d(it->second[0], it->second[1], it->second[2]);
    }
    bool bone_has(uint32_t v, std::initializer_list<const char*> parts) const {
        for (const char* p : parts)
            if (t_.vertex_bone[v].find(p) != std::string::npos) return true;
        return false;
    }
    // The vertex of the region (predicate) furthest along dir.
    uint32_t extreme(const std::function<bool(uint32_t)>& in, const Vector3d& dir) const {
        uint32_t best = format::kNone;
        double best_d = -std::numeric_limits<double>::max();
        for (uint32_t v = 0; v < t_.xyz.size() / 3; ++v) {
            if (!in(v)) continue;
            const double d = vertex(v).dot(dir);
            if (d > best_d) best_d = d, best = v;
        }
        return best;
    }
    // The first surface point hit by the ray origin + t dir, t > 0 (Moller-Trumbore).
    Hit ray(const Vector3d& origin, const Vector3d& dir) const {
        Hit best;
        best.t = std::numeric_limits<double>::max();
        const Vector3d d = dir.normalized();
        for (uint32_t tri = 0; tri < t_.triangles.size() / 3; ++tri) {
            const Vector3d a = vertex(t_.triangles[3 * tri]), b = vertex(t_.triangles[3 * tri + 1]), c = vertex(t_.triangles[3 * tri + 2]);
            const Vector3d e1 = b - a, e2 = c - a, p = d.cross(e2);
            const double det = e1.dot(p);
            if (std::abs(det) < 1e-14) continue;
            const Vector3d s = origin - a;
            const double u = s.dot(p) / det;
            if (u < 0 || u > 1) continue;
            const Vector3d q = s.cross(e1);
            const double v = d.dot(q) / det;
            if (v < 0 || u + v > 1) continue;
            const double t = e2.dot(q) / det;
            if (t > 1e-6 && t < best.t) best = Hit{tri, u, v, t};
        }
        return best;
    }

    void add_vertex(const std::string& name, uint32_t v) {
        if (v == format::kNone) fail(SSC_ERROR_INTERNAL, "landmark rule for '" + name + "' found no vertex");
        format::Landmark l;
        l.name = name;
        l.vertex = v;
        out.push_back(l);
    }
    void add_hit(const std::string& name, const Hit& h) {
        if (h.triangle == format::kNone) fail(SSC_ERROR_INTERNAL, "landmark rule for '" + name + "' found no surface");
        format::Landmark l;
        l.name = name;
        l.triangle = h.triangle;
        l.barycentric[0] = float(1 - h.u - h.v);
        l.barycentric[1] = float(h.u);
        l.barycentric[2] = float(h.v);
        out.push_back(l);
    }
    // A ray from outside the body: from `at` moved 1 m against dir, travelling along dir.
    Hit from_outside(const Vector3d& at, const Vector3d& dir) const { return ray(at - dir.normalized(), dir); }

    std::vector<format::Landmark> out;

private:
    const LandmarkTemplate& t_;
};

}  // namespace

LandmarkTemplate landmark_template(const format::ModelData& m, const float* rest_xyz) {
    const uint32_t V = m.vertex_count(), J = uint32_t(m.skeleton.joint_names.size());
    LandmarkTemplate t;
    t.xyz.assign(rest_xyz, rest_xyz + 3 * std::size_t(V));
    t.triangles.assign(m.mesh.triangles.begin(), m.mesh.triangles.end());
    for (uint32_t v = 0; v < V; ++v) t.vertex_bone.push_back(m.skeleton.joint_names[m.skin.joints[4 * std::size_t(v)]]);
    const auto& sk = m.skeleton;
    const std::vector<float> joints =
        apply_regressor(sk.regressor_offsets.data(), sk.regressor_vertices.data(), sk.regressor_weights.data(), J, rest_xyz);
    for (uint32_t j = 0; j < J; ++j) t.joints[sk.joint_names[j]].assign(&joints[3 * j], &joints[3 * j] + 3);
    return t;
}

Eigen::Vector3d landmark_position(const format::Landmark& l, const float* xyz, const uint32_t* triangles) {
    auto vertex = [&](uint32_t v) { return Vector3d(xyz[3 * std::size_t(v)], xyz[3 * std::size_t(v) + 1], xyz[3 * std::size_t(v) + 2]); };
    if (l.vertex != format::kNone) return vertex(l.vertex);
    const uint32_t* c = &triangles[3 * std::size_t(l.triangle)];
    return l.barycentric[0] * vertex(c[0]) + l.barycentric[1] * vertex(c[1]) + l.barycentric[2] * vertex(c[2]);
}

const std::vector<std::string>& caesar_names() {
    static const std::vector<std::string> names = {
        "Sellion", "Rt. Infraorbitale", "Lt. Infraorbitale", "Supramenton", "Rt. Tragion", "Rt. Gonion", "Lt. Tragion",
        "Lt. Gonion", "Nuchale", "Rt. Clavicale", "Suprasternale", "Lt. Clavicale", "Rt. Thelion/Bustpoint",
        "Lt. Thelion/Bustpoint", "Substernale", "Rt. 10th Rib", "Rt. ASIS", "Lt. 10th Rib", "Lt. ASIS", "Rt. Iliocristale",
        "Rt. Trochanterion", "Lt. Iliocristale", "Lt. Trochanterion", "Cervicale", "10th Rib Midspine", "Rt. PSIS",
        "Lt. PSIS", "Waist, Preferred, Post.", "Rt. Acromion", "Rt. Axilla, Ant", "Rt. Radial Styloid", "Rt. Axilla, Post.",
        "Rt. Olecranon", "Rt. Humeral Lateral Epicn", "Rt. Humeral Medial Epicn", "Rt. Radiale", "Rt. Metacarpal Phal. II",
        "Rt. Dactylion", "Rt. Ulnar Styloid", "Rt. Metacarpal-Phal. V", "Lt. Acromion", "Lt. Axilla, Ant",
        "Lt. Radial Styloid", "Lt. Axilla, Post.", "Lt. Olecranon", "Lt. Humeral Lateral Epicn", "Lt. Humeral Medial Epicn",
        "Lt. Radiale", "Lt. Metacarpal-Phal. II", "Lt. Dactylion", "Lt. Ulnar Styloid", "Lt. Metacarpal-Phal. V",
        "Rt. Knee Crease", "Rt. Femoral Lateral Epicn", "Rt. Femoral Medial Epicn", "Rt. Metatarsal-Phal. V",
        "Rt. Lateral Malleolus", "Rt. Medial Malleolus", "Rt. Sphyrion", "Rt. Metatarsal-Phal. I", "Rt. Calcaneous, Post.",
        "Rt. Digit II", "Lt. Knee Crease", "Lt. Femoral Lateral Epicn", "Lt. Femoral Medial Epicn", "Lt. Metatarsal-Phal. V",
        "Lt. Lateral Malleolus", "Lt. Medial Malleolus", "Lt. Sphyrion", "Lt. Metatarsal-Phal. I", "Lt. Calcaneous, Post.",
        "Lt. Digit II", "Crotch"};
    return names;
}

std::vector<format::Landmark> place_caesar_landmarks(const LandmarkTemplate& t) {
    Placer P(t);
    const Vector3d X = Vector3d::UnitX(), Y = Vector3d::UnitY(), Z = Vector3d::UnitZ();
    std::map<std::string, format::Landmark> by_name;
    auto keep = [&] {
        by_name[P.out.back().name] = P.out.back();
    };
    auto add_v = [&](const std::string& n, uint32_t v) { P.add_vertex(n, v); keep(); };
    auto add_h = [&](const std::string& n, const Hit& h) { P.add_hit(n, h); keep(); };
    auto pos = [&](const std::string& n) { return landmark_position(by_name.at(n), t.xyz.data(), t.triangles.data()); };
    const Vector3d head = P.joint("head"), neck = P.joint("neck_01"), spine3 = P.joint("spine_03"), spine1 = P.joint("spine_01");
    const Vector3d pelvis = P.joint("pelvis");
    auto is_head = [&](uint32_t v) { return P.bone_has(v, {"head", "neck"}); };
    // Stature: heights below are fractions of it where anatomy gives proportions, not distances.
    double floor_y = std::numeric_limits<double>::max(), top_y = -floor_y;
    for (std::size_t v = 0; v < t.xyz.size() / 3; ++v) floor_y = std::min(floor_y, double(t.xyz[3 * v + 1])), top_y = std::max(top_y, double(t.xyz[3 * v + 1]));
    const double H = top_y - floor_y;
    // The middle of the trunk's depth at a height: halfway between its front and back on the midline.
    auto trunk_mid_depth = [&](double y) {
        const Hit front = P.from_outside(Vector3d(0, y, pelvis.z()), -Z), back = P.from_outside(Vector3d(0, y, pelvis.z()), Z);
        if (front.triangle == format::kNone || back.triangle == format::kNone) fail(SSC_ERROR_INTERNAL, "a trunk landmark found no trunk");
        return pelvis.z() + 0.5 * (back.t - front.t);  // front at z0 + 1 - tf, back at z0 - 1 + tb
    };
    // A fold of the armpit (dir +Z: anterior, -Z: posterior) of the arm on side s with shoulder joint sh.
    auto axilla = [&](const Vector3d& sh, double s, const Vector3d& dir) {
        const double y = sh.y() - 0.15;
        const Hit trunk = P.ray(Vector3d(0, y, sh.z()), s * Vector3d::UnitX());  // out through the side of the trunk
        if (trunk.triangle == format::kNone) fail(SSC_ERROR_INTERNAL, "an Axilla rule found no trunk");
        const Vector3d side(s * (trunk.t + 0.001), y, sh.z());
        const Hit arm = P.ray(side, s * Vector3d::UnitX());  // across the gap to the arm
        if (arm.triangle == format::kNone) fail(SSC_ERROR_INTERNAL, "an Axilla rule found no arm");
        const Hit dome = P.ray(side + s * 0.5 * arm.t * Vector3d::UnitX(), Vector3d::UnitY());  // up into the armpit
        if (dome.triangle == format::kNone) fail(SSC_ERROR_INTERNAL, "an Axilla rule found no armpit");
        // Down the fold from 3 cm above the dome, seen from the front (back): the skin faces that way,
        // then turns under into the armpit. The fold's lower edge, the landmark, is where it turns
        // past 45 degrees (its depth falls faster than the height over 3 mm).
        const double x = side.x() + s * 0.5 * arm.t, dome_y = y + dome.t;
        std::vector<std::pair<double, Hit>> down;  // depth in front of (behind) the joint, hit
        for (double fy = dome_y + 0.03; fy > dome_y - 0.03; fy -= 0.001) {
            const Hit h = P.from_outside(Vector3d(x, fy, sh.z()), -dir);
            if (h.triangle == format::kNone) break;
            down.emplace_back(1.0 - h.t, h);  // the hit lies at sh.z + (1 - t) dir
        }
        Hit fold;
        for (std::size_t i = 0; i < down.size(); ++i) {
            if (i >= 3 && down[i - 3].first - down[i].first > 0.003) break;
            fold = down[i].second;
        }
        return fold;
    };
    auto midline = [&](uint32_t v, double w) { return std::abs(P.vertex(v).x()) < w; };

    // Midline profiles of the head, as seen: rays along the midline from in front (face profile) and
    // from behind (back profile), one per millimetre of height. Rays cannot pick inner surfaces
    // (mouth, nostrils) the way vertex searches can.
    struct ProfilePoint {
        double y, z;
        Hit hit;
    };
    std::vector<ProfilePoint> face, nape;
    for (double y = neck.y(); y < head.y() + 0.25; y += 0.001) {
        const Hit f = P.from_outside(Vector3d(0, y, head.z()), -Z);
        if (f.triangle != format::kNone) face.push_back({y, head.z() + 1.0 - f.t, f});
        const Hit b = P.from_outside(Vector3d(0, y, head.z()), Z);
        if (b.triangle != format::kNone) nape.push_back({y, head.z() - 1.0 + b.t, b});
    }
    auto profile_extreme = [&](const std::vector<ProfilePoint>& prof, double y0, double y1, double sign) {
        const ProfilePoint* best = nullptr;
        for (const auto& p : prof)
            if (p.y >= y0 && p.y <= y1 && (!best || sign * p.z > sign * best->z)) best = &p;
        if (!best) fail(SSC_ERROR_INTERNAL, "a head profile landmark found no surface");
        return *best;
    };
    // Pronasale (nose tip): the most anterior point of the face profile.
    const double ny = profile_extreme(face, neck.y() + 0.02, head.y() + 0.25, 1).y;
    // 1 Sellion: the deepest point of the nasal root, the most posterior face-profile point within
    // 5 cm above the nose tip.
    add_h("Sellion", profile_extreme(face, ny + 0.005, ny + 0.05, -1).hit);
    // 4 Supramenton (CAESAR: the deepest point of the hollow between the lower lip and the chin, on
    // the front of the face): walk down the face profile from the lower lip to the first hollow. The lower
    // lip (labrale inferius) is the most anterior point within 2.5 cm below the mouth slit; the slit
    // is where a profile ray enters the mouth (a sample 1 cm behind its neighbours), or, with closed
    // lips, the deepest point between the lips. Profile rays that enter the mouth are dropped: the
    // old rule picked one and put this landmark 10 cm inside the mouth.
    std::vector<ProfilePoint> outer;
    double slit = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t i = 0; i < face.size(); ++i) {
        const double above = i + 1 < face.size() ? face[i + 1].z : face[i].z, below = i > 0 ? face[i - 1].z : face[i].z;
        if (face[i].z < std::min(above, below) - 0.01) {
            if (face[i].y > ny - 0.045 && face[i].y < ny - 0.01) slit = face[i].y;
            continue;
        }
        outer.push_back(face[i]);
    }
    if (std::isnan(slit)) slit = profile_extreme(outer, ny - 0.035, ny - 0.015, -1).y;
    const double lower_lip = profile_extreme(outer, slit - 0.025, slit - 0.001, 1).y;
    const ProfilePoint* fold = nullptr;
    for (auto it = outer.rbegin(); it != outer.rend(); ++it) {  // top to bottom
        if (it->y >= lower_lip) continue;
        if (fold && it->z > fold->z + 0.0002) break;  // the profile turns forward again: the chin
        if (!fold || it->z < fold->z) fold = &*it;
        if (it->y < lower_lip - 0.03) break;  // no chin bulge (receding chin): stop 3 cm down
    }
    if (!fold) fail(SSC_ERROR_INTERNAL, "the Supramenton rule found no chin");
    add_h("Supramenton", fold->hit);
    // 24 Cervicale: the spinous process of C7 at the base of the neck: straight behind the neck joint.
    add_h("Cervicale", P.ray(neck - 0.01 * Y, -Z));
    // 11 Suprasternale: the jugular notch, midline front at the height of the clavicle joints.
    const Vector3d cl = P.joint("clavicle_l"), cr = P.joint("clavicle_r");
    add_h("Suprasternale", P.from_outside(Vector3d(0, 0.5 * (cl.y() + cr.y()), spine3.z()), -Z));
    const Vector3d sst = pos("Suprasternale");

    for (int side = -1; side <= 1; side += 2) {
        const std::string S = side < 0 ? "Rt. " : "Lt. ";
        const std::string sfx = side < 0 ? "_r" : "_l";
        const double s = side;
        // 2/3 Infraorbitale: the lowest point of the eye socket's rim, on the face 3.2 cm lateral of
        // the midline, midway between the sellion and the nose tip.
        const Vector3d sel = pos("Sellion");
        add_h(S + "Infraorbitale", P.ray(Vector3d(s * 0.032, 0.5 * (sel.y() + ny), head.z()), Z));
        // 5/7 Tragion: the notch in front of the ear. The ear is the most lateral part of the head
        // (the outer 1.5 cm); the tragion is its most anterior point at the ear's mean height.
        const uint32_t ear_out = P.extreme([&](uint32_t v) { return is_head(v) && s * P.vertex(v).x() > 0 && P.vertex(v).y() > neck.y() + 0.05; }, s * X);
        const double ear_x = P.vertex(ear_out).x();
        double ear_y = 0;
        int ear_n = 0;
        auto in_ear = [&](uint32_t v) { return is_head(v) && s * P.vertex(v).x() > s * ear_x - 0.015 && P.vertex(v).y() > neck.y() + 0.05; };
        for (uint32_t v = 0; v < t.xyz.size() / 3; ++v)
            if (in_ear(v)) ear_y += P.vertex(v).y(), ++ear_n;
        ear_y /= std::max(1, ear_n);
        const uint32_t tragion = P.extreme([&](uint32_t v) { return in_ear(v) && std::abs(P.vertex(v).y() - ear_y) < 0.01; }, Z);
        add_v(S + "Tragion", tragion);
        // 6/8 Gonion: the angle of the jaw, 4 cm below and 1.5 cm in front of the tragion, on the side.
        const Vector3d tr = P.vertex(tragion);
        // Seen from outside (above the shoulders): a ray from the midline could meet the mouth's inside.
        add_h(S + "Gonion", P.from_outside(Vector3d(s * 0.0, tr.y() - 0.04, tr.z() + 0.015), -s * X));
        // 10/12 Clavicale: the medial end of the clavicle, 2.5 cm lateral of the suprasternale.
        add_h(S + "Clavicale", P.from_outside(Vector3d(s * 0.025, sst.y() + 0.005, sst.z()), -Z));
        // 13/14 Thelion/Bustpoint: the most anterior point of the chest on each side.
        add_v(S + "Thelion/Bustpoint", P.extreme([&](uint32_t v) {
            const Vector3d p = P.vertex(v);
            return !is_head(v) && !P.bone_has(v, {"arm", "hand", "thumb", "index", "middle", "ring", "pinky"}) && s * p.x() > 0.04 &&
                   s * p.x() < 0.16 && p.y() < sst.y() - 0.05 && p.y() > sst.y() - 0.30;
        }, Z));
        // 29/41 Acromion (CAESAR and ISO 8559-1: the lateral edge of the acromion): straight above
        // the shoulder joint, 1.5 cm out.
        const Vector3d sh = P.joint("upperarm" + sfx);
        add_h(S + "Acromion", P.ray(sh + s * 0.015 * X, Y));
        // 30/42 and 32/44 Axilla, Ant. / Post. (CAESAR: the lowest points of the front / back armpit
        // folds, where the arm meets the chest / back): find the armpit's dome with a ray
        // up through the gap between the trunk and the arm 15 cm below the shoulder, then follow the
        // front (back) skin down to the fold's lower edge. The old rule took fixed offsets from the
        // shoulder joint and was 4-10 cm off on real scans.
        add_h(S + "Axilla, Ant", axilla(sh, s, Z));
        add_h(S + "Axilla, Post.", axilla(sh, s, -Z));
        // Elbow: the forearm axis and the lateral direction (away from the body in the frontal plane).
        const Vector3d el = P.joint("lowerarm" + sfx), wr = P.joint("hand" + sfx);
        const Vector3d axis = (wr - el).normalized();
        Vector3d lateral = axis.cross(Z).normalized();
        if (lateral.x() * s < 0) lateral = -lateral;
        add_h(S + "Olecranon", P.ray(el, -Z));                       // 33/45 tip of the elbow, behind the joint
        add_h(S + "Humeral Lateral Epicn", P.ray(el, lateral));      // 34/46 outer bump of the elbow
        add_h(S + "Humeral Medial Epicn", P.ray(el, -lateral));      // 35/47 inner bump of the elbow
        add_h(S + "Radiale", P.ray(el + 0.02 * axis, lateral));      // 36/48 head of the radius, 2 cm below
        // Wrist (A-pose: palms face the thighs, thumbs forward): radial styloid on the thumb side (front),
        // ulnar styloid on the little-finger side (back), 1 cm above the wrist joint.
        // The rays cross the forearm at right angles: along Z itself they cut the forward-slanting
        // forearm obliquely and met the thumb's base, 10 cm from the ulnar styloid.
        const Vector3d forward = (Z - Z.dot(axis) * axis).normalized();
        add_h(S + "Radial Styloid", P.ray(wr - 0.01 * axis, forward));
        add_h(S + "Ulnar Styloid", P.ray(wr - 0.01 * axis, -forward));
        // Knuckles (metacarpophalangeal joints II and V) on the back of the hand (lateral in A-pose).
        add_h(S + (side < 0 ? "Metacarpal Phal. II" : "Metacarpal-Phal. II"), P.ray(P.joint("index_01" + sfx), lateral));
        add_h(S + "Metacarpal-Phal. V", P.ray(P.joint("pinky_01" + sfx), lateral));
        // 38/50 Dactylion: the tip of the middle finger, furthest along the finger.
        const Vector3d m1 = P.joint("middle_01" + sfx), m3 = P.joint("middle_03" + sfx);
        add_v(S + "Dactylion", P.extreme([&](uint32_t v) { return P.bone_has(v, {("middle_03" + sfx).c_str()}); }, (m3 - m1).normalized()));

        // Torso.
        const Vector3d hip = P.joint("thigh" + sfx);
        // 20/22 Iliocristale (CAESAR: the highest point of the hip bone's crest, at the side of the
        // body, in the mid-axillary line): 7.5 % of stature above the hip joint (the crest stands about
        // 12 cm above the femoral head in an adult pelvis), at mid-depth of the trunk at that height.
        const double crest_y = hip.y() + 0.075 * H;
        const double crest_z = trunk_mid_depth(crest_y);
        add_h(S + "Iliocristale", P.ray(Vector3d(0, crest_y, crest_z), s * X));
        // 16/18 10th Rib (CAESAR: the lowest point of the lower border of the rib cage, the 10th rib,
        // on the front-side of the torso below the chest): one lumbar vertebra (2.5 % of stature) above the iliac
        // crest, as the subcostal plane (L3) lies one vertebra above the supracristal plane (L4);
        // three quarters of the way from the midline to the side, on the front. The old rule put it
        // on the side of the trunk 5 cm higher: on real scans it was 10-16 cm off, mostly too far back.
        const double rib_level = crest_y + 0.025 * H;
        const Hit side_hit = P.ray(Vector3d(0, rib_level, trunk_mid_depth(rib_level)), s * X);
        if (side_hit.triangle == format::kNone) fail(SSC_ERROR_INTERNAL, "the 10th Rib rule found no side of the trunk");
        add_h(S + "10th Rib", P.from_outside(Vector3d(s * 0.75 * side_hit.t, rib_level, pelvis.z()), -Z));
        // 17/19 ASIS (CAESAR: the anterior superior iliac spine, the front tip of the crest): on
        // the front, over the hip joint, 7 cm above it.
        add_h(S + "ASIS", P.from_outside(Vector3d(hip.x(), hip.y() + 0.07, pelvis.z()), -Z));
        // 21/23 Trochanterion (CAESAR: the top of the femur's greater trochanter): straight out from the hip
        // joint, level with the femoral head.
        add_h(S + "Trochanterion", P.ray(hip, s * X));
        // 26/27 PSIS (CAESAR: the posterior superior iliac spine, the dimples above the buttocks):
        // at the second sacral vertebra, 4 % of stature (about 7 cm) below the iliac crest's top,
        // 4.5 cm off the midline.
        add_h(S + "PSIS", P.from_outside(Vector3d(s * 0.045, crest_y - 0.04 * H, pelvis.z()), Z));

        // Leg.
        const Vector3d knee = P.joint("calf" + sfx), ankle = P.joint("foot" + sfx), ball = P.joint("ball" + sfx);
        add_h(S + "Knee Crease", P.ray(knee, -Z));                    // 53/63 behind the knee joint
        add_h(S + "Femoral Lateral Epicn", P.ray(knee, s * X));       // 54/64 outer side of the knee
        add_h(S + "Femoral Medial Epicn", P.ray(knee, -s * X));       // 55/65 inner side of the knee
        add_h(S + "Lateral Malleolus", P.ray(ankle, s * X));          // 57/67 outer ankle bone
        add_h(S + "Medial Malleolus", P.ray(ankle, -s * X));          // 58/68 inner ankle bone
        add_h(S + "Sphyrion", P.ray(ankle - 0.015 * Y, -s * X));      // 59/69 tip of the medial malleolus, 1.5 cm lower
        add_h(S + "Metatarsal-Phal. V", P.ray(ball, s * X));          // 56/66 ball of the foot, outer side
        add_h(S + "Metatarsal-Phal. I", P.ray(ball, -s * X));         // 60/70 ball of the foot, inner side
        auto is_foot = [&](uint32_t v) { return P.bone_has(v, {("foot" + sfx).c_str(), ("ball" + sfx).c_str()}); };
        add_v(S + "Calcaneous, Post.", P.extreme(is_foot, -Z));       // 61/71 back of the heel
        // 62/72 Digit II: the tip of the second toe: the most anterior toe point, leaving out the big
        // toe's 1.5 cm on the inner side.
        add_v(S + "Digit II", P.extreme([&](uint32_t v) { return is_foot(v) && s * P.vertex(v).x() > s * ball.x() - 0.005; }, Z));
    }
    // 15 Substernale: the lower end of the sternum, midline front 17 cm below the suprasternale.
    add_h("Substernale", P.from_outside(Vector3d(0, sst.y() - 0.17, spine3.z()), -Z));
    // 25 10th Rib Midspine: the midline of the back at the height of the 10th ribs.
    const double rib_y = 0.5 * (pos("Rt. 10th Rib").y() + pos("Lt. 10th Rib").y());
    add_h("10th Rib Midspine", P.from_outside(Vector3d(0, rib_y, spine1.z()), Z));
    // 28 Waist, Preferred, Post. (CAESAR: on the back midline at the subject's preferred waist, where
    // the subject wears the waistband): at the height of the iliac crests, the belt line. The old
    // rule took the narrowest trunk level and was up to 17 cm too high on real scans.
    const double crest = 0.5 * (pos("Rt. Iliocristale").y() + pos("Lt. Iliocristale").y());
    add_h("Waist, Preferred, Post.", P.from_outside(Vector3d(0, crest, spine1.z()), Z));
    // 9 Nuchale (CAESAR: the lowest midline point of the back of the skull, where the neck
    // muscles attach): on the back profile of the head 2.5 cm below the tragions' height, the
    // underside of the occiput. The old rule took the deepest point of the neck, 6 cm lower.
    const double nuchale_y = 0.5 * (pos("Rt. Tragion").y() + pos("Lt. Tragion").y()) - 0.025;
    const ProfilePoint* nuchale = nullptr;
    for (const auto& p : nape)
        if (!nuchale || std::abs(p.y - nuchale_y) < std::abs(nuchale->y - nuchale_y)) nuchale = &p;
    if (!nuchale) fail(SSC_ERROR_INTERNAL, "the Nuchale rule found no back of the head");
    add_h("Nuchale", nuchale->hit);
    // 73 Crotch: the lowest midline point of the trunk, where the legs part.
    add_v("Crotch", P.extreme([&](uint32_t v) { return midline(v, 0.004) && P.vertex(v).y() < pelvis.y() && !is_head(v); }, -Y));

    // CAESAR order.
    std::vector<format::Landmark> ordered;
    for (const auto& n : caesar_names()) {
        const auto it = by_name.find(n);
        if (it == by_name.end()) fail(SSC_ERROR_INTERNAL, "no rule placed the landmark '" + n + "'");
        ordered.push_back(it->second);
    }
    return ordered;
}

}  // namespace ssc::training
