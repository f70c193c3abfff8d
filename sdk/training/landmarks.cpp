#include "landmarks.hpp"

#include "common/error.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <limits>

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
    auto pos = [&](const std::string& n) {
        const auto& l = by_name.at(n);
        if (l.vertex != format::kNone) return P.vertex(l.vertex);
        const uint32_t* c = &t.triangles[3 * l.triangle];
        return Vector3d(l.barycentric[0] * P.vertex(c[0]) + l.barycentric[1] * P.vertex(c[1]) + l.barycentric[2] * P.vertex(c[2]));
    };
    const Vector3d head = P.joint("head"), neck = P.joint("neck_01"), spine3 = P.joint("spine_03"), spine1 = P.joint("spine_01");
    const Vector3d pelvis = P.joint("pelvis");
    auto is_head = [&](uint32_t v) { return P.bone_has(v, {"head", "neck"}); };
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
    // 4 Supramenton: the deepest point of the concavity between lower lip and chin: the most
    // posterior face-profile point between the lower lip (most anterior point 2 to 4.5 cm below the
    // nose tip) and the chin (most anterior point 4.5 to 9 cm below it).
    const double lip = profile_extreme(face, ny - 0.045, ny - 0.02, 1).y;
    const double chin = profile_extreme(face, ny - 0.09, ny - 0.045, 1).y;
    add_h("Supramenton", profile_extreme(face, chin, lip, -1).hit);
    // 9 Nuchale: where the back of the skull meets the neck, the most anterior back-profile point
    // between the neck joint and the head joint.
    add_h("Nuchale", profile_extreme(nape, neck.y(), head.y() + 0.02, 1).hit);
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
        // 29/41 Acromion: the lateral tip of the shoulder, straight above the shoulder joint, 1.5 cm out.
        const Vector3d sh = P.joint("upperarm" + sfx);
        add_h(S + "Acromion", P.ray(sh + s * 0.015 * X, Y));
        // 30/42 and 32/44 Axilla: the front and back folds of the armpit, 8 cm below the shoulder joint
        // and 3 cm medial of it.
        add_h(S + "Axilla, Ant", P.ray(sh + Vector3d(-s * 0.03, -0.08, 0), Z));
        add_h(S + "Axilla, Post.", P.ray(sh + Vector3d(-s * 0.03, -0.08, 0), -Z));
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
        add_h(S + "Radial Styloid", P.ray(wr - 0.01 * axis, Z));
        add_h(S + "Ulnar Styloid", P.ray(wr - 0.01 * axis, -Z));
        // Knuckles (metacarpophalangeal joints II and V) on the back of the hand (lateral in A-pose).
        add_h(S + (side < 0 ? "Metacarpal Phal. II" : "Metacarpal-Phal. II"), P.ray(P.joint("index_01" + sfx), lateral));
        add_h(S + "Metacarpal-Phal. V", P.ray(P.joint("pinky_01" + sfx), lateral));
        // 38/50 Dactylion: the tip of the middle finger, furthest along the finger.
        const Vector3d m1 = P.joint("middle_01" + sfx), m3 = P.joint("middle_03" + sfx);
        add_v(S + "Dactylion", P.extreme([&](uint32_t v) { return P.bone_has(v, {("middle_03" + sfx).c_str()}); }, (m3 - m1).normalized()));

        // Torso.
        const Vector3d hip = P.joint("thigh" + sfx);
        // 16/18 10th Rib: the lowest point of the rib cage at the side, 22 cm below the suprasternale,
        // 3 cm in front of the spine (rays go from inside the trunk out, so hanging arms never block).
        add_h(S + "10th Rib", P.ray(Vector3d(0, sst.y() - 0.22, spine1.z() + 0.03), s * X));
        // 17/19 ASIS: the front of the iliac crest, 7 cm above the hip joint, over the hip joint.
        add_h(S + "ASIS", P.from_outside(Vector3d(hip.x(), hip.y() + 0.07, pelvis.z()), -Z));
        // 20/22 Iliocristale: the top of the iliac crest at the side, 11 cm above the hip joint.
        add_h(S + "Iliocristale", P.ray(Vector3d(0, hip.y() + 0.11, pelvis.z()), s * X));
        // 21/23 Trochanterion: the top of the greater trochanter: straight out from the hip joint.
        add_h(S + "Trochanterion", P.ray(hip, s * X));
        // 26/27 PSIS: the dimples over the posterior iliac spines, 4.5 cm off the midline, 6 cm above the hip joint.
        add_h(S + "PSIS", P.from_outside(Vector3d(s * 0.045, hip.y() + 0.06, pelvis.z()), Z));

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
    // 28 Waist, Preferred, Post.: midline of the back at the natural waist, the height between the
    // 10th ribs and the iliac crests where the torso is narrowest.
    const double crest_y = 0.5 * (pos("Rt. Iliocristale").y() + pos("Lt. Iliocristale").y());
    double waist_y = rib_y, narrowest = std::numeric_limits<double>::max();
    for (double y = crest_y; y <= rib_y; y += 0.005) {
        const Hit l = P.ray(Vector3d(0, y, spine1.z()), X), r = P.ray(Vector3d(0, y, spine1.z()), -X);
        if (l.triangle == format::kNone || r.triangle == format::kNone) continue;
        const double width = l.t + r.t;  // from the midline out to each side
        if (width < narrowest) narrowest = width, waist_y = y;
    }
    add_h("Waist, Preferred, Post.", P.from_outside(Vector3d(0, waist_y, spine1.z()), Z));
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
