// Retrains a small model from the MakeHuman assets (when ../shared/makehuman is there) so the
// training pipeline cannot rot, and checks its quality numbers.
#include "support.hpp"

#include "common/error.hpp"
#include "training/landmarks.hpp"
#include "training/makehuman/assets.hpp"
#include "training/train.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace {

// A small training run's settings, or false (with a visible skip) where the assets are absent.
bool small_training(ssc::training::TrainSpec& spec) {
    const std::string root = test::makehuman_root();
    if (root.empty()) {
        WARN("SKIPPED: ../shared/makehuman not found (set SSCAPE_MAKEHUMAN to its path to run this test)");
        return false;
    }
    spec.assets_root = root;
    spec.population.count = 160;
    spec.components = 10;
    spec.heldout = 30;
    return true;
}

}  // namespace

TEST_CASE("MakeHuman macro rules follow the asset README", "[training]") {
    using ssc::training::mh::macro_weight;
    ssc::training::mh::MacroSliders s;
    s.gender = 0.25;
    s.weight = 0.75;
    CHECK(macro_weight({"male"}, s) == Approx(0.25));
    CHECK(macro_weight({"female"}, s) == Approx(0.75));
    CHECK(macro_weight({"maxweight"}, s) == Approx(0.5));
    CHECK(macro_weight({"averageweight"}, s) == Approx(0.5));
    CHECK(macro_weight({"minweight"}, s) == Approx(0.0));
    CHECK(macro_weight({"universal", "female", "maxweight"}, s) == Approx(0.375));
    s.age = 1.0;
    CHECK(macro_weight({"old"}, s) == Approx(1.0));
    CHECK(macro_weight({"young"}, s) == Approx(0.0));
    CHECK(ssc::training::mh::age_years(0.5) == Approx(25.0));
    CHECK(ssc::training::mh::age_slider(90.0) == Approx(1.0));
    CHECK(ssc::training::mh::age_slider(ssc::training::mh::age_years(0.3)) == Approx(0.3));
}

TEST_CASE("training reports its stages and bodies and stops when the progress callback says so", "[training][makehuman]") {
    ssc::training::TrainSpec spec;
    if (!small_training(spec)) return;
    // Sampling the population (each body's stature and weight calibrated) reports every body and
    // stops at once: it once ran for a minute and a half deaf to Ctrl-C.
    {
        uint32_t sampled = 0, of = 0;
        const ssc::training::Progress stop_sampling = [&](const std::string& stage, uint32_t done, uint32_t total) {
            if (stage == "sampling bodies") sampled = done, of = total;
            return !(stage == "sampling bodies" && done == 3);
        };
        ssc::training::TrainReport report;
        try {
            ssc::training::train_model(spec, report, stop_sampling);
            FAIL("sampling went on after the callback returned false");
        } catch (const ssc::Error& e) {
            CHECK(e.status() == SSC_ERROR_CANCELLED);
        }
        CHECK(sampled == 3);
        CHECK(of == 160);
    }
    std::vector<std::string> stages;
    uint32_t last_done = 0, total = 0, sampled = 0;
    const ssc::training::Progress stop_at_body_5 = [&](const std::string& stage, uint32_t done, uint32_t of) {
        if (stages.empty() || stages.back() != stage) stages.push_back(stage);
        if (stage == "sampling bodies") sampled = std::max(sampled, done + 1);
        if (of) last_done = done, total = of;
        return !(stage == "generating bodies" && done == 5);
    };
    ssc::training::TrainReport report;
    try {
        ssc::training::train_model(spec, report, stop_at_body_5);
        FAIL("training went on after the callback returned false");
    } catch (const ssc::Error& e) {
        CHECK(e.status() == SSC_ERROR_CANCELLED);
    }
    REQUIRE(stages.size() == 4);  // loading, sampling (announced, then body by body), generating
    CHECK(stages[2] == "sampling bodies");
    CHECK(sampled == 160);
    CHECK(stages.back() == "generating bodies");
    CHECK(last_done == 5);
    CHECK(total == 160);
}

TEST_CASE("a small model retrained from the MakeHuman assets meets its quality numbers", "[training][makehuman]") {
    ssc::training::TrainSpec spec;
    if (!small_training(spec)) return;
    spec.population.seed = 3;
    spec.made_to_measure_bodies = 8;
    spec.segment_components = 4;
    ssc::training::TrainReport report;
    const auto model = ssc::training::train_model(spec, report);
    REQUIRE(model.vertex_count() == 13380);
    REQUIRE(model.joint_count() == 53);
    REQUIRE(model.component_count() == 10);
    // Compactness: a handful of components explain nearly all variation of this population.
    double cum = 0;
    for (double sd : report.stddev) cum += sd * sd;
    CHECK(cum / report.total_variance > 0.97);
    // Stature follows the survey figures it was calibrated to (men taller than women, plausible means).
    double men = 0, women = 0;
    int nm = 0, nw = 0;
    for (std::size_t i = 0; i < report.statures.size(); ++i)
        (report.male[i] ? (men += report.statures[i], ++nm) : (women += report.statures[i], ++nw));
    REQUIRE(nm > 10);
    REQUIRE(nw > 10);
    CHECK(men / nm == Approx(1.75).margin(0.03));
    CHECK(women / nw == Approx(1.61).margin(0.03));
    // Joints follow the shape: held-out regressor error in millimetres, not centimetres.
    CHECK(report.regressor_mean_error < 0.006);
    CHECK(report.quantization.max_error <= 1e-4);
    // Joint limits and the attribute model (sliders, made to measure) are learned and stored.
    CHECK(model.joint_limits.size() == 21);  // 5 spine, neck and head joints, 8 on each side
    CHECK(model.joint_roles.size() == 53);    // the table's roles, as model data
    REQUIRE(model.attributes.attributes.size() >= 15);
    int sliders = 0;
    for (const auto& a : model.attributes.attributes) sliders += a.slider;
    CHECK(sliders >= 6);
    // Bodies made to measure from held-out bodies' own measurements reach them within 1 cm.
    const auto& mtm = report.made_to_measure;
    REQUIRE(mtm.bodies == 8);
    REQUIRE(mtm.measurements.size() == 4);
    for (std::size_t k = 0; k < 4; ++k) {
        INFO(mtm.measurements[k]);
        CHECK(mtm.mean_error[k] < 0.003);
        CHECK(mtm.worst_error[k] < 0.01);
    }

    // The 73 CAESAR landmarks, in CAESAR order, placed where anatomy puts them.
    REQUIRE(model.landmarks.size() == 73);
    const auto& names = ssc::training::caesar_names();
    for (std::size_t i = 0; i < 73; ++i) CHECK(model.landmarks[i].name == names[i]);

    // The written model loads and synthesizes a body of plausible height.
    auto m = test::load(ssc::format::write_model(model));
    REQUIRE(m);
    auto b = test::body(m.get());
    const auto v = test::posed(m.get(), b.get());
    float lo = 1e9f, hi = -1e9f;
    for (std::size_t i = 1; i < v.size(); i += 3) lo = std::min(lo, v[i]), hi = std::max(hi, v[i]);
    CHECK(hi - lo == Approx(1.68).margin(0.08));
    CHECK(lo == Approx(0.0).margin(0.02));  // standing on the ground

    std::vector<float> lm(3 * 73);
    REQUIRE(ssc_model_get_landmark_positions(m.get(), lm.data(), 73, 0) == SSC_OK);
    auto at = [&](const char* name) {
        uint32_t i = 0;
        REQUIRE(ssc_model_find_landmark(m.get(), name, &i) == SSC_OK);
        return std::array<float, 3>{lm[3 * i], lm[3 * i + 1], lm[3 * i + 2]};
    };
    // Left/right pairs mirror each other (the asset is symmetric); the subject's left is +X.
    for (std::size_t i = 0; i < 73; ++i) {
        const std::string& n = names[i];
        if (n.rfind("Lt. ", 0) != 0) continue;
        std::string rt = "Rt. " + n.substr(4);
        if (rt == "Rt. Metacarpal-Phal. II") rt = "Rt. Metacarpal Phal. II";  // CAESAR's own spelling
        const auto l = at(n.c_str()), r = at(rt.c_str());
        CHECK(l[0] > 0.02f);
        CHECK(l[0] == Approx(-r[0]).margin(0.01));
        CHECK(l[1] == Approx(r[1]).margin(0.01));
        CHECK(l[2] == Approx(r[2]).margin(0.01));
    }
    // Top-to-bottom order along the body.
    const char* column[] = {"Sellion", "Supramenton", "Suprasternale", "Substernale", "Crotch", "Lt. Knee Crease",
                            "Lt. Lateral Malleolus"};
    for (int i = 0; i + 1 < 7; ++i) CHECK(at(column[i])[1] > at(column[i + 1])[1]);
    // Front and back: the bust point is in front of the suprasternale, cervicale behind it.
    CHECK(at("Lt. Thelion/Bustpoint")[2] > at("Suprasternale")[2]);
    CHECK(at("Cervicale")[2] < at("Suprasternale")[2] - 0.05f);
    CHECK(at("Lt. Calcaneous, Post.")[2] < at("Lt. Digit II")[2] - 0.15f);

    // Segment shape spaces over the same bodies: six, each holding more of its own variance with
    // its own first components than the whole body's first components hold of it; and a body built
    // from an arm's coefficients moves that arm, not the other.
    REQUIRE(model.segments.size() == 6);
    REQUIRE(report.segments.size() == 6);
    for (const auto& s : report.segments) {
        INFO(s.name << ": own " << s.own[0] << ", whole body " << s.whole_body[0]);
        REQUIRE(s.own.size() == 4);
        CHECK(s.own[0] >= s.whole_body[0] - 1e-9);
        CHECK(s.own[3] > 0.5);
    }
    CHECK(model.metadata.provenance.find("segment shape spaces: 4 components each") != std::string::npos);
    uint32_t arm_l = 0, arm_r = 0;
    REQUIRE(ssc_model_find_segment(m.get(), "arm_l", &arm_l) == SSC_OK);
    REQUIRE(ssc_model_find_segment(m.get(), "arm_r", &arm_r) == SSC_OK);
    const float coefficients[1] = {3.f};
    REQUIRE(ssc_body_set_segment_shape(b.get(), arm_l, coefficients, 1) == SSC_OK);
    const auto moved = test::posed(m.get(), b.get());
    double left = 0, right = 0;
    for (std::size_t i = 0; i < v.size(); i += 3) {
        const double d = std::hypot(moved[i] - v[i], moved[i + 1] - v[i + 1], moved[i + 2] - v[i + 2]);
        if (v[i] > 0.3f) left = std::max(left, d);  // the subject's left is +X
        if (v[i] < -0.3f) right = std::max(right, d);
    }
    INFO("arm_l at +3 SD moves the left hand side up to " << left * 1e3 << " mm, the right " << right * 1e3 << " mm");
    CHECK(left > 0.005);
    CHECK(right < 1e-6);
}
