// Segment shape spaces: learned per body segment, stored in the file, set per body through the C API.
#include "learning/learn_model.hpp"
#include "support.hpp"

#include "common/error.hpp"
#include "simulation/simulate.hpp"
#include "sscape_format/model_io.hpp"
#include "synthesis/body.hpp"
#include "synthesis/model.hpp"
#include "training/segment_shapes.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

using namespace ssc;

namespace {

// Bodies of the default model's whole shape space at rest: registrations with nothing to normalize.
std::vector<scan_files::RegisteredScan> rest_bodies(const Model& m, uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<float> pose(4 * std::size_t(m.joint_count()), 0.f);
    for (uint32_t j = 0; j < m.joint_count(); ++j) pose[4 * j + 3] = 1.f;
    std::vector<scan_files::RegisteredScan> out;
    for (uint32_t i = 0; i < count; ++i) {
        scan_files::RegisteredScan s;
        s.name = "body" + std::to_string(i);
        s.vertices = simulation::make_body(m, simulation::random_shape(m, rng), pose, Eigen::Vector3d::Zero()).vertices;
        out.push_back(std::move(s));
    }
    return out;
}

// One learned model with segments for the tests below (learning takes a few seconds).
const format::ModelData& learned_with_segments(learning::LearnReport* report_out = nullptr) {
    static learning::LearnReport report;
    static const format::ModelData model = [] {
        const Model& m = test::default_cpp_model();
        learning::LearnSpec spec;
        spec.components = 12;
        spec.posture = learning::Posture::None;
        spec.segment_components = 6;
        return learning::learn_model(m.data(), rest_bodies(m, 40, 5), spec, &report);
    }();
    if (report_out) *report_out = report;
    return model;
}

std::vector<float> rest_of(ssc_body* body, uint32_t V) {
    std::vector<float> out(3ull * V);
    REQUIRE(ssc_body_get_rest_vertices(body, out.data(), V, 0) == SSC_OK);
    return out;
}

}  // namespace

TEST_CASE("segment layout: six segments that partition the body and blend across their borders", "[segments]") {
    const format::ModelData& d = test::default_cpp_model().data();
    const auto layout = training::segment_layout(d, 0.08);
    REQUIRE(layout.size() == 6);
    std::vector<double> sum(d.vertex_count(), 0.0);
    std::size_t blended = 0;
    for (const auto& s : layout)
        for (std::size_t i = 0; i < s.vertices.size(); ++i) {
            sum[s.vertices[i]] += s.weights[i];
            blended += s.weights[i] < 0.99f;
        }
    for (double w : sum) REQUIRE(std::abs(w - 1) < 1e-3);  // every vertex, fully
    CHECK(blended > 1000);                                  // the bands
    const auto hard = training::segment_layout(d, 0.0);
    for (const auto& s : hard)
        for (float w : s.weights) REQUIRE(w == 1.f);
    CHECK_THROWS_WITH(training::segment_layout(d, 0.9), Catch::Contains("blend band"));
    CHECK_THROWS_WITH(training::segment_layout(test::mini_model().data, 0.08), Catch::Contains("no vertex set"));
}

TEST_CASE("segment shape spaces: each segment's own components hold more of it than the whole body's", "[segments]") {
    learning::LearnReport report;
    const format::ModelData& learned = learned_with_segments(&report);
    REQUIRE(learned.segments.size() == 6);
    REQUIRE(report.segments.size() == 6);
    for (const auto& s : report.segments) {
        INFO(s.name << ": own " << s.own[0] << " " << s.own[2] << " " << s.own[5] << ", whole body " << s.whole_body[0] << " "
                    << s.whole_body[2] << " " << s.whole_body[5]);
        REQUIRE(s.own.size() == 6);
        REQUIRE(s.whole_body.size() == 6);
        for (std::size_t k = 0; k < 6; ++k) {
            CHECK(s.own[k] >= s.whole_body[k] - 1e-3);  // PCA is the best k directions for the segment's own data
            if (k) CHECK(s.own[k] >= s.own[k - 1]);
        }
        CHECK(s.own[5] > 0.9);
    }
    CHECK(learned.metadata.provenance.find("segment shape spaces: 6 components") != std::string::npos);
}

TEST_CASE("segment shape spaces survive the file and move only their part of a body", "[segments]") {
    const format::ModelData& learned = learned_with_segments();
    const std::vector<unsigned char> bytes = format::write_model(learned);
    const format::ModelData back = format::read_model(bytes.data(), bytes.size());
    REQUIRE(back.segments.size() == learned.segments.size());
    for (std::size_t s = 0; s < back.segments.size(); ++s) {
        CHECK(back.segments[s].name == learned.segments[s].name);
        CHECK(back.segments[s].vertices == learned.segments[s].vertices);
        CHECK(back.segments[s].weights == learned.segments[s].weights);
        CHECK(back.segments[s].stddev == learned.segments[s].stddev);
        CHECK(back.segments[s].basis.q == learned.segments[s].basis.q);
    }

    test::ModelPtr model = test::load(bytes);
    REQUIRE(model);
    REQUIRE(ssc_model_segment_count(model.get()) == 6);
    uint32_t arm = 0, torso = 0, missing = 0;
    REQUIRE(ssc_model_find_segment(model.get(), "arm_l", &arm) == SSC_OK);
    REQUIRE(ssc_model_find_segment(model.get(), "torso", &torso) == SSC_OK);
    CHECK(ssc_model_find_segment(model.get(), "tail", &missing) == SSC_ERROR_NOT_FOUND);
    ssc_segment_info info{};
    info.struct_size = sizeof info;
    REQUIRE(ssc_model_get_segment_info(model.get(), arm, &info) == SSC_OK);
    CHECK(std::string(info.name) == "arm_l");
    CHECK(info.shape_count == 6);
    std::vector<uint32_t> arm_vertices(info.vertex_count);
    std::vector<float> arm_weights(info.vertex_count);
    REQUIRE(ssc_model_get_segment_vertices(model.get(), arm, arm_vertices.data(), arm_weights.data(), info.vertex_count) == SSC_OK);

    const uint32_t V = ssc_model_vertex_count(model.get());
    ssc_body* raw = nullptr;
    REQUIRE(ssc_body_create(model.get(), nullptr, &raw) == SSC_OK);
    test::BodyPtr body(raw);
    const float shape[3] = {1.f, -0.5f, 0.3f};
    REQUIRE(ssc_body_set_shape(body.get(), shape, 3) == SSC_OK);
    const std::vector<float> base = rest_of(body.get(), V);

    // An arm's coefficients: the arm and its band move, nothing else does.
    const float arm_c[2] = {2.f, -1.f};
    REQUIRE(ssc_body_set_segment_shape(body.get(), arm, arm_c, 2) == SSC_OK);
    float back_c[6];
    REQUIRE(ssc_body_get_segment_shape(body.get(), arm, back_c, 6) == SSC_OK);
    CHECK(back_c[0] == 2.f);
    CHECK(back_c[1] == -1.f);
    CHECK(back_c[2] == 0.f);
    const std::vector<float> moved = rest_of(body.get(), V);
    std::vector<char> in_arm(V, 0);
    for (uint32_t v : arm_vertices) in_arm[v] = 1;
    double outside = 0, inside = 0;
    for (uint32_t v = 0; v < V; ++v)
        for (int a = 0; a < 3; ++a) {
            const double d = std::abs(double(moved[3 * v + a]) - base[3 * v + a]);
            (in_arm[v] ? inside : outside) = std::max(in_arm[v] ? inside : outside, d);
        }
    INFO("largest move: in the arm " << inside * 1e3 << " mm, elsewhere " << outside * 1e3 << " mm");
    CHECK(outside == 0);
    CHECK(inside > 0.01);
    // Whole-body setters leave the segment coefficients alone; the shapes add.
    REQUIRE(ssc_body_set_shape(body.get(), nullptr, 0) == SSC_OK);
    REQUIRE(ssc_body_get_segment_shape(body.get(), arm, back_c, 6) == SSC_OK);
    CHECK(back_c[0] == 2.f);
    REQUIRE(ssc_body_set_shape(body.get(), shape, 3) == SSC_OK);
    const std::vector<float> again = rest_of(body.get(), V);
    for (uint32_t i = 0; i < 3 * V; ++i) REQUIRE(again[i] == moved[i]);

    // The torso's coefficients carry the hand along rigidly: every hand vertex moves the same.
    REQUIRE(ssc_body_set_segment_shape(body.get(), arm, nullptr, 0) == SSC_OK);
    const float torso_c[1] = {3.f};
    REQUIRE(ssc_body_set_segment_shape(body.get(), torso, torso_c, 1) == SSC_OK);
    const std::vector<float> carried = rest_of(body.get(), V);
    const Model& cpp = test::default_cpp_model();
    const auto hands = std::find_if(cpp.data().vertex_sets.begin(), cpp.data().vertex_sets.end(), [](const auto& s) { return s.name == "hands"; });
    REQUIRE(hands != cpp.data().vertex_sets.end());
    Eigen::Vector3d first_move = Eigen::Vector3d::Zero();
    double spread = 0;
    bool first = true;
    for (uint32_t v : hands->vertices) {
        if (learned.shape.mean[3 * v] < 0) continue;  // the left hand (+X)
        Eigen::Vector3d d;
        for (int a = 0; a < 3; ++a) d[a] = double(carried[3 * v + a]) - base[3 * v + a];
        if (first) first_move = d, first = false;
        spread = std::max(spread, (d - first_move).norm());
    }
    INFO("the left hand moves " << first_move.norm() * 1e3 << " mm, its vertices within " << spread * 1e6 << " um of each other");
    CHECK(spread < 2e-5);

    // The joints follow: the regressor of the rest vertices.
    const Model learned_model(learned, nullptr);
    Body cpp_body(learned_model, nullptr);
    cpp_body.set_segment_shape(uint32_t(torso), torso_c, 1);
    cpp_body.set_segment_shape(uint32_t(arm), arm_c, 2);
    const float* rest = cpp_body.rest_planar();
    const float* joints = cpp_body.rest_joints();
    const auto& sk = learned.skeleton;
    double joint_error = 0;
    for (uint32_t j = 0; j < learned_model.joint_count(); ++j)
        for (uint32_t a = 0; a < 3; ++a) {
            double x = 0;
            for (uint32_t e = sk.regressor_offsets[j]; e < sk.regressor_offsets[j + 1]; ++e)
                x += sk.regressor_weights[e] * rest[a * V + sk.regressor_vertices[e]];
            joint_error = std::max(joint_error, std::abs(x - joints[3 * j + a]));
        }
    CHECK(joint_error < 1e-5);
}

TEST_CASE("segment shape spaces refuse bad input with a clear message", "[segments]") {
    const format::ModelData& learned = learned_with_segments();
    test::ModelPtr model = test::load(format::write_model(learned));
    REQUIRE(model);
    ssc_body* raw = nullptr;
    REQUIRE(ssc_body_create(model.get(), nullptr, &raw) == SSC_OK);
    test::BodyPtr body(raw);
    const float ok[1] = {1.f}, nan[1] = {std::nanf("")}, huge[1] = {1e6f}, many[7] = {0, 0, 0, 0, 0, 0, 0};
    CHECK(ssc_body_set_segment_shape(nullptr, 0, ok, 1) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_segment_shape(body.get(), 6, ok, 1) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(ssc_last_error()).find("out of range") != std::string::npos);
    CHECK(ssc_body_set_segment_shape(body.get(), 0, many, 7) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_segment_shape(body.get(), 0, nullptr, 1) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_segment_shape(body.get(), 0, nan, 1) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_segment_shape(body.get(), 0, huge, 1) == SSC_ERROR_INVALID_ARGUMENT);
    float out[6];
    CHECK(ssc_body_get_segment_shape(body.get(), 0, out, 5) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_body_get_segment_shape(body.get(), 0, nullptr, 6) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_get_segment_info(model.get(), 0, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    ssc_segment_info info{};
    CHECK(ssc_model_get_segment_info(model.get(), 0, &info) == SSC_ERROR_INVALID_ARGUMENT);  // struct_size unset
    uint32_t small[4];
    CHECK(ssc_model_get_segment_vertices(model.get(), 0, small, nullptr, 4) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_model_find_segment(model.get(), nullptr, small) == SSC_ERROR_INVALID_ARGUMENT);
    // A model without segments.
    test::ModelPtr plain = test::load(test::mini_bytes());
    CHECK(ssc_model_segment_count(plain.get()) == 0);
    CHECK(ssc_model_segment_count(nullptr) == 0);
    CHECK(ssc_model_get_segment_vertices(plain.get(), 0, small, nullptr, 4) == SSC_ERROR_INVALID_ARGUMENT);

    // Files whose segments break the rules are refused whole, naming the problem.
    auto refused = [&](const std::function<void(format::ModelData&)>& damage, const char* message) {
        format::ModelData d = learned;
        damage(d);
        format::WriteOptions no_check;
        no_check.validate = false;
        const std::vector<unsigned char> bytes = format::write_model(d, no_check);
        ssc_model* m = nullptr;
        CHECK(ssc_model_load_memory(nullptr, bytes.data(), bytes.size(), &m) == SSC_ERROR_MODEL_CORRUPT);
        CHECK_THAT(ssc_last_error(), Catch::Contains(message));
        CHECK(m == nullptr);
    };
    refused([](format::ModelData& d) {  // an arm vertex that is all arm given to the torso too (the torso lists every vertex)
        const auto& arm = d.segments[1];
        const auto i = std::size_t(std::find(arm.weights.begin(), arm.weights.end(), 1.f) - arm.weights.begin());
        d.segments[3].weights[arm.vertices.at(i)] = 0.5f;
    }, "sum to over 1");
    refused([](format::ModelData& d) { d.segments[0].weights[3] = std::nanf(""); }, "weights must lie in [0, 1]");
    refused([](format::ModelData& d) { std::swap(d.segments[0].vertices[0], d.segments[0].vertices[1]); }, "sorted and unique");
    refused([](format::ModelData& d) { d.segments[2].name = d.segments[0].name; }, "repeats the name");
    refused([](format::ModelData& d) { d.segments[0].stddev[0] = -1.f; }, "stddev and step");

    // Learning: too few bodies for the segment components, a band too narrow to blend, no body parts.
    const Model& m = test::default_cpp_model();
    learning::LearnSpec spec;
    spec.components = 3;
    spec.posture = learning::Posture::None;
    spec.segment_components = 8;
    const auto bodies = rest_bodies(m, 6, 9);
    CHECK_THROWS_WITH(learning::learn_model(m.data(), bodies, spec), Catch::Contains("components per segment"));
    spec.segment_components = 3;
    spec.segment_band = 0.001;
    CHECK_THROWS_WITH(learning::learn_model(m.data(), bodies, spec), Catch::Contains("blend band"));
    spec.segment_band = 0.08;
    format::ModelData partless = m.data();
    partless.vertex_sets.clear();
    CHECK_THROWS_WITH(learning::learn_model(partless, bodies, spec), Catch::Contains("no vertex set"));
}
