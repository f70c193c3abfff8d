// The 73 CAESAR landmarks of the shipped default model stand where the anatomical definitions
// (shared/docs/landmarks.md, the survey's own descriptions) put them, on women, men and bodies far
// from the mean: each landmark is checked against its neighbours (above/below, in front/behind,
// medial/lateral), in the model frame (metres, +Y up, facing +Z, the subject's left at +X).
// The shipped landmarks are also exactly what today's rules give on the model's mean.
#include "support.hpp"
#include "training/landmarks.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Core>

#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using Eigen::Vector3f;

struct Landmarks {
    std::map<std::string, Vector3f> at;
    float stature = 0;
    const Vector3f& operator[](const std::string& n) const { return at.at(n); }
};

Landmarks landmarks_of(ssc_model* m, ssc_body* b) {
    const uint32_t L = ssc_model_landmark_count(m), V = ssc_model_vertex_count(m);
    std::vector<float> p(3 * std::size_t(L)), v(3 * std::size_t(V));
    REQUIRE(ssc_body_get_landmarks(b, p.data(), L, 0) == SSC_OK);
    REQUIRE(ssc_body_get_vertices(b, v.data(), V, 0) == SSC_OK);
    Landmarks out;
    for (uint32_t i = 0; i < L; ++i) {
        const char* name = nullptr;
        REQUIRE(ssc_model_get_landmark_name(m, i, &name) == SSC_OK);
        out.at[name] = Vector3f(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    }
    float lo = 1e9f, hi = -1e9f;
    for (uint32_t i = 0; i < V; ++i) lo = std::min(lo, v[3 * i + 1]), hi = std::max(hi, v[3 * i + 1]);
    out.stature = hi - lo;
    return out;
}

// CAESAR spells the right index knuckle without the hyphen.
std::string side_name(const char* side, const std::string& n) {
    if (std::string(side) == "Rt. " && n == "Metacarpal-Phal. II") return "Rt. Metacarpal Phal. II";
    return side + n;
}

void check_anatomy(const Landmarks& L) {
    auto y = [&](const std::string& n) { return L[n].y(); };
    auto z = [&](const std::string& n) { return L[n].z(); };
    auto ax = [&](const std::string& n) { return std::abs(L[n].x()); };
    const float H = L.stature;

    // Midline landmarks lie on the mid-sagittal plane (within 1 cm: random bodies far out are a
    // little asymmetric).
    for (const char* n : {"Sellion", "Supramenton", "Nuchale", "Suprasternale", "Substernale", "Cervicale", "10th Rib Midspine",
                          "Waist, Preferred, Post.", "Crotch"}) {
        INFO(n);
        CHECK(ax(n) < 0.01f);
    }

    // Head. Sellion: the nasal root, on the front of the face, above the eye sockets' lower rims.
    CHECK(y("Sellion") - y("Lt. Infraorbitale") > 0.005f);
    CHECK(y("Sellion") - y("Lt. Infraorbitale") < 0.04f);
    CHECK(z("Sellion") > z("Lt. Tragion") + 0.06f);
    // Infraorbitale and tragion define the Frankfort horizontal: about level with each other.
    CHECK(std::abs(y("Lt. Infraorbitale") - y("Lt. Tragion")) < 0.025f);
    CHECK(ax("Lt. Infraorbitale") > 0.02f);
    CHECK(ax("Lt. Infraorbitale") < 0.05f);
    // Supramenton: on the front of the face below the mouth, not under the jaw or inside the mouth.
    CHECK(y("Lt. Infraorbitale") - y("Supramenton") > 0.04f);
    CHECK(y("Lt. Infraorbitale") - y("Supramenton") < 0.10f);
    CHECK(z("Supramenton") > z("Lt. Gonion") + 0.04f);
    CHECK(z("Supramenton") > z("Sellion") - 0.03f);
    // Tragion: the ear, the widest of the head landmarks; the gonion (jaw angle) 2-6 cm below it.
    CHECK(ax("Lt. Tragion") > ax("Lt. Gonion"));
    CHECK(y("Lt. Tragion") - y("Lt. Gonion") > 0.02f);
    CHECK(y("Lt. Tragion") - y("Lt. Gonion") < 0.07f);
    CHECK(z("Lt. Gonion") < z("Supramenton"));
    // Nuchale: the underside of the occiput, behind and a little below the ears, well above the
    // base of the neck.
    CHECK(z("Nuchale") < z("Lt. Tragion") - 0.05f);
    CHECK(y("Lt. Tragion") - y("Nuchale") > 0.005f);
    CHECK(y("Lt. Tragion") - y("Nuchale") < 0.05f);
    CHECK(y("Nuchale") - y("Cervicale") > 0.06f);

    // Neck and chest.
    CHECK(z("Cervicale") < z("Suprasternale") - 0.06f);  // the back of the neck's base
    CHECK(y("Cervicale") > y("Suprasternale"));
    CHECK(y("Cervicale") < y("Lt. Gonion"));
    CHECK(std::abs(y("Lt. Clavicale") - y("Suprasternale")) < 0.02f);
    CHECK(ax("Lt. Clavicale") > 0.01f);
    CHECK(ax("Lt. Clavicale") < 0.05f);
    CHECK(ax("Lt. Thelion/Bustpoint") > 0.05f);
    CHECK(ax("Lt. Thelion/Bustpoint") < 0.15f);
    CHECK(y("Suprasternale") - y("Lt. Thelion/Bustpoint") > 0.10f);
    CHECK(y("Suprasternale") - y("Lt. Thelion/Bustpoint") < 0.25f);
    CHECK(z("Lt. Thelion/Bustpoint") > z("Suprasternale"));
    CHECK(y("Suprasternale") - y("Substernale") > 0.12f);
    CHECK(y("Suprasternale") - y("Substernale") < 0.24f);
    // 10th Rib: below the sternum, on the front-side of the trunk, one vertebra above the iliac crest.
    CHECK(y("Substernale") - y("Lt. 10th Rib") > 0.05f);
    CHECK(y("Lt. 10th Rib") - y("Lt. Iliocristale") > 0.01f);
    CHECK(y("Lt. 10th Rib") - y("Lt. Iliocristale") < 0.08f);
    CHECK(z("Lt. 10th Rib") > z("Lt. Iliocristale") + 0.03f);
    CHECK(ax("Lt. 10th Rib") > 0.05f);
    CHECK(ax("Lt. 10th Rib") < ax("Lt. Iliocristale"));
    // Level with the 10th ribs on the mean; carried by the surface, within 4 cm on extreme bodies.
    CHECK(std::abs(y("10th Rib Midspine") - y("Lt. 10th Rib")) < 0.04f);
    CHECK(z("10th Rib Midspine") < z("Lt. 10th Rib") - 0.06f);

    // Waist and pelvis. Iliocristale: the side of the crest, about at 60 % of stature, above the
    // front (ASIS) and back (PSIS) spines and the trochanter.
    CHECK(y("Lt. Iliocristale") / H > 0.56f);
    CHECK(y("Lt. Iliocristale") / H < 0.65f);
    CHECK(y("Lt. Iliocristale") - y("Lt. ASIS") > 0.02f);
    CHECK(y("Lt. Iliocristale") - y("Lt. ASIS") < 0.10f);
    CHECK(y("Lt. Iliocristale") - y("Lt. PSIS") > 0.03f);
    CHECK(std::abs(y("Lt. ASIS") - y("Lt. PSIS")) < 0.04f);
    CHECK(z("Lt. ASIS") > z("Lt. PSIS") + 0.12f);
    CHECK(ax("Lt. PSIS") > 0.02f);
    CHECK(ax("Lt. PSIS") < 0.07f);
    CHECK(ax("Lt. ASIS") < ax("Lt. Iliocristale"));
    CHECK(y("Lt. ASIS") > y("Lt. Trochanterion"));
    CHECK(y("Lt. Trochanterion") / H > 0.47f);
    CHECK(y("Lt. Trochanterion") / H < 0.56f);
    CHECK(ax("Lt. Trochanterion") > ax("Lt. ASIS"));
    // The preferred waist (the belt line) at the iliac crests, on the back.
    CHECK(std::abs(y("Waist, Preferred, Post.") - y("Lt. Iliocristale")) < 0.035f);
    CHECK(z("Waist, Preferred, Post.") < z("Lt. Iliocristale"));
    CHECK(y("Lt. Trochanterion") > y("Crotch"));
    CHECK(y("Crotch") / H > 0.42f);
    CHECK(y("Crotch") / H < 0.52f);

    for (const char* S : {"Rt. ", "Lt. "}) {
        INFO(S);
        const float s = std::string(S) == "Lt. " ? 1.f : -1.f;
        auto p = [&](const std::string& n) { return L[side_name(S, n)]; };
        // Every paired landmark on its own side.
        for (const char* n : {"Infraorbitale", "Tragion", "Gonion", "Clavicale", "Thelion/Bustpoint", "10th Rib", "ASIS", "Iliocristale",
                              "Trochanterion", "PSIS", "Acromion", "Axilla, Ant", "Axilla, Post.", "Olecranon", "Humeral Lateral Epicn",
                              "Humeral Medial Epicn", "Radiale", "Radial Styloid", "Ulnar Styloid", "Metacarpal-Phal. II",
                              "Metacarpal-Phal. V", "Dactylion", "Knee Crease", "Femoral Lateral Epicn", "Femoral Medial Epicn",
                              "Lateral Malleolus", "Medial Malleolus", "Sphyrion", "Metatarsal-Phal. I", "Metatarsal-Phal. V",
                              "Calcaneous, Post.", "Digit II"}) {
            INFO(n);
            CHECK(s * p(n).x() > 0.01f);
        }
        // Arm. The acromion is the edge of the shoulder, above the armpit folds.
        CHECK(p("Acromion").y() - p("Axilla, Ant").y() > 0.07f);
        CHECK(p("Acromion").y() - p("Axilla, Ant").y() < 0.22f);
        CHECK(p("Acromion").y() - p("Axilla, Post.").y() > 0.07f);
        CHECK(p("Acromion").y() - p("Axilla, Post.").y() < 0.22f);
        CHECK(p("Axilla, Ant").z() > p("Axilla, Post.").z() + 0.02f);
        CHECK(s * p("Acromion").x() > s * p("Axilla, Ant").x() - 0.03f);
        CHECK(p("Acromion").y() > L["Suprasternale"].y() - 0.03f);
        // Elbow: the olecranon behind, the lateral epicondyle further out than the medial one, the
        // radius head just below the lateral epicondyle.
        const Vector3f elbow = 0.5f * (p("Humeral Lateral Epicn") + p("Humeral Medial Epicn"));
        CHECK(p("Olecranon").z() < elbow.z() - 0.01f);
        CHECK(s * p("Humeral Lateral Epicn").x() > s * p("Humeral Medial Epicn").x() + 0.02f);
        CHECK((p("Radiale") - p("Humeral Lateral Epicn")).norm() < 0.05f);
        CHECK(p("Radiale").y() < p("Humeral Lateral Epicn").y() + 0.01f);
        // Wrist (palms towards the thighs, thumbs forward): radial styloid in front of the ulnar one.
        CHECK(p("Radial Styloid").z() > p("Ulnar Styloid").z() + 0.02f);
        CHECK((p("Radial Styloid") - p("Ulnar Styloid")).norm() < 0.09f);  // the wrist's breadth
        // Hand: knuckles beyond the wrist, the middle fingertip furthest from the shoulder.
        const Vector3f sh = p("Acromion");
        const float wrist = (p("Radial Styloid") - sh).norm();
        CHECK((p("Metacarpal-Phal. II") - sh).norm() > wrist);
        CHECK((p("Metacarpal-Phal. V") - sh).norm() > wrist);
        for (const char* n : {"Olecranon", "Radial Styloid", "Ulnar Styloid", "Metacarpal-Phal. II", "Metacarpal-Phal. V"})
            CHECK((p("Dactylion") - sh).norm() > (p(n) - sh).norm());
        CHECK(p("Dactylion").y() / H > 0.30f);
        CHECK(p("Dactylion").y() / H < 0.60f);

        // Knee: crease behind, lateral epicondyle further out than the medial one; about 28 % of stature.
        CHECK(p("Knee Crease").z() < p("Femoral Lateral Epicn").z() - 0.02f);
        CHECK(s * p("Femoral Lateral Epicn").x() > s * p("Femoral Medial Epicn").x() + 0.06f);
        CHECK(p("Femoral Lateral Epicn").y() / H > 0.24f);
        CHECK(p("Femoral Lateral Epicn").y() / H < 0.33f);
        // Ankle and foot: malleoli either side, the sphyrion just below the medial one, the heel
        // behind everything and the second toe in front, the big-toe joint medial of the fifth.
        CHECK(s * p("Lateral Malleolus").x() > s * p("Medial Malleolus").x() + 0.03f);
        CHECK(std::abs(p("Lateral Malleolus").y() - p("Medial Malleolus").y()) < 0.02f);
        CHECK(p("Medial Malleolus").y() - p("Sphyrion").y() > 0.005f);
        CHECK(p("Medial Malleolus").y() - p("Sphyrion").y() < 0.03f);
        CHECK(p("Medial Malleolus").y() / H > 0.03f);
        CHECK(p("Medial Malleolus").y() / H < 0.07f);
        CHECK(p("Calcaneous, Post.").z() < p("Medial Malleolus").z() - 0.02f);
        CHECK(p("Digit II").z() > p("Metatarsal-Phal. I").z() + 0.03f);
        CHECK(s * p("Metatarsal-Phal. V").x() > s * p("Metatarsal-Phal. I").x() + 0.05f);
        CHECK(p("Metatarsal-Phal. I").y() < 0.05f * H);
    }
}

}  // namespace

TEST_CASE("the default model's landmarks follow the CAESAR definitions on women, men and extreme bodies", "[landmarks]") {
    test::DefaultBody d;
    ssc_model* m = d.model;
    ssc_body* b = d.body;
    REQUIRE(ssc_model_landmark_count(m) == 73);
    uint32_t sex = 0, stature = 0, mass = 0;
    REQUIRE(ssc_model_find_slider(m, "sex", &sex) == SSC_OK);
    REQUIRE(ssc_model_find_slider(m, "stature", &stature) == SSC_OK);
    REQUIRE(ssc_model_find_slider(m, "mass", &mass) == SSC_OK);
    ssc_slider_info st{}, ms{};
    st.struct_size = ms.struct_size = sizeof(ssc_slider_info);
    REQUIRE(ssc_model_get_slider_info(m, stature, &st) == SSC_OK);
    REQUIRE(ssc_model_get_slider_info(m, mass, &ms) == SSC_OK);

    SECTION("the mean body") { check_anatomy(landmarks_of(m, b)); }
    SECTION("a woman and a man, each short and tall, light and heavy") {
        for (float s : {0.f, 1.f})
            for (float h : {st.minimum, st.maximum})
                for (float kg : {ms.minimum, ms.maximum}) {
                    INFO("sex " << s << " stature " << h << " mass " << kg);
                    REQUIRE(ssc_body_set_shape(b, nullptr, 0) == SSC_OK);
                    REQUIRE(ssc_body_set_slider(b, sex, s) == SSC_OK);
                    REQUIRE(ssc_body_set_slider(b, stature, h) == SSC_OK);
                    REQUIRE(ssc_body_set_slider(b, mass, kg * (h / st.maximum) * (h / st.maximum)) == SSC_OK);
                    check_anatomy(landmarks_of(m, b));
                }
    }
    SECTION("random bodies at 2.5 standard deviations") {
        std::mt19937 rng(20);
        std::normal_distribution<float> n(0.f, 1.f);
        std::vector<float> c(ssc_model_shape_count(m));
        for (int k = 0; k < 12; ++k) {
            float norm = 0;
            for (float& x : c) x = n(rng), norm += x * x;
            for (float& x : c) x *= 2.5f / std::sqrt(norm);  // a body 2.5 SD from the mean
            INFO("random body " << k);
            REQUIRE(ssc_body_set_shape(b, c.data(), uint32_t(c.size())) == SSC_OK);
            check_anatomy(landmarks_of(m, b));
        }
    }
}

TEST_CASE("the shipped landmarks are what the rules place on the model's mean", "[landmarks]") {
    // Compared as positions: a build with other floating-point contractions (the shipped model was
    // made by an x86-64-v3 build) moves a ray's hit in the last bits.
    const auto data = ssc::format::read_model_file(test::default_model_file());
    const auto& mean = data.shape.mean;
    const auto placed = ssc::training::place_caesar_landmarks(ssc::training::landmark_template(data, mean.data()));
    auto position = [&](const ssc::format::Landmark& l) { return ssc::training::landmark_position(l, mean.data(), data.mesh.triangles.data()); };
    REQUIRE(placed.size() == data.landmarks.size());
    for (std::size_t i = 0; i < placed.size(); ++i) {
        INFO(placed[i].name);
        CHECK(placed[i].name == data.landmarks[i].name);
        CHECK((position(placed[i]) - position(data.landmarks[i])).norm() < 5e-4);
    }
}
