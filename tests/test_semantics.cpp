// Joint limits from the model file, semantic sliders and bodies made to measure, through the C API
// on the default model.
#include "support.hpp"

#include "semantics/attribute_model.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

uint32_t joint(ssc_model* m, const char* name) {
    uint32_t j = 0;
    REQUIRE(ssc_model_find_joint(m, name, &j) == SSC_OK);
    return j;
}

std::vector<float> identity_pose(ssc_model* m) {
    std::vector<float> q(4ull * ssc_model_joint_count(m), 0.f);
    for (std::size_t j = 0; j < q.size() / 4; ++j) q[4 * j + 3] = 1.f;
    return q;
}

// Anatomical angles of a local rotation under a limit (the header's definition).
Eigen::Vector3d angles(const ssc_joint_limit& l, const float* q) {
    const Eigen::AngleAxisd aa(Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized());
    const Eigen::Vector3d r = aa.angle() * aa.axis();
    Eigen::Matrix3d F;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) F(a, b) = l.frame[3 * a + b];
    return F * r;
}

std::vector<float> measure_all(ssc_body* b) {
    std::vector<float> v(ssc_measurement_count());
    REQUIRE(ssc_body_measure(b, v.data(), uint32_t(v.size())) == SSC_OK);
    return v;
}

uint32_t slider(ssc_model* m, const char* name) {
    uint32_t i = 0;
    REQUIRE(ssc_model_find_slider(m, name, &i) == SSC_OK);
    return i;
}

}  // namespace

TEST_CASE("joint limits come from the model file and are enforced when a pose is set", "[semantics][limits]") {
    const auto m = test::default_model();
    REQUIRE(m);
    const auto b = test::body(m.get());
    ssc_joint_limit knee{}, finger{};
    const uint32_t calf = joint(m.get(), "calf_l");
    REQUIRE(ssc_model_get_joint_limit(m.get(), calf, &knee) == SSC_OK);
    REQUIRE(knee.limited == 1);
    CHECK(knee.upper[0] > 2.0f);   // knee flexion, about 133 degrees
    CHECK(knee.lower[0] > -0.3f);  // no hyperextension beyond a few degrees
    REQUIRE(ssc_model_get_joint_limit(m.get(), joint(m.get(), "index_01_l"), &finger) == SSC_OK);
    CHECK(finger.limited == 0);
    CHECK(ssc_model_get_joint_limit(m.get(), ssc_model_joint_count(m.get()), &knee) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_model_get_joint_limit(m.get(), 0, nullptr) == SSC_ERROR_INVALID_ARGUMENT);

    // A knee bent 60 degrees the wrong way: the flexion axis is the frame's first row.
    std::vector<float> q = identity_pose(m.get());
    const Eigen::Vector3d axis(knee.frame[0], knee.frame[1], knee.frame[2]);
    const Eigen::Quaterniond bad(Eigen::AngleAxisd(-60 * M_PI / 180, axis));
    float* qk = &q[4 * std::size_t(calf)];
    qk[0] = float(bad.x()), qk[1] = float(bad.y()), qk[2] = float(bad.z()), qk[3] = float(bad.w());
    CHECK(angles(knee, qk)[0] == Approx(-60 * M_PI / 180).margin(1e-4));

    const std::vector<float> before = test::posed(m.get(), b.get());
    uint32_t violations = 99;
    CHECK(ssc_body_set_pose_limited(b.get(), q.data(), uint32_t(q.size() / 4), nullptr, SSC_LIMITS_REJECT, &violations) ==
          SSC_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(ssc_last_error()).find("calf_l") != std::string::npos);
    CHECK(violations == 1);
    CHECK(test::posed(m.get(), b.get()) == before);  // nothing set

    REQUIRE(ssc_body_set_pose_limited(b.get(), q.data(), uint32_t(q.size() / 4), nullptr, SSC_LIMITS_CLAMP, &violations) == SSC_OK);
    CHECK(violations == 1);
    CHECK(test::posed(m.get(), b.get()) != before);
    // The clamped knee sits on its lower bound: pose it again from the body's own transforms is not
    // exposed, so check the clamp by re-running it on the clamped rotation: nothing left to clamp.
    std::vector<float> clamped = q;
    {
        Eigen::Quaterniond r(qk[3], qk[0], qk[1], qk[2]);
        Eigen::Matrix3d F;
        for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c) F(a, c) = knee.frame[3 * a + c];
        Eigen::Vector3d a = angles(knee, qk);
        for (int i = 0; i < 3; ++i) a[i] = std::min<double>(std::max<double>(a[i], knee.lower[i]), knee.upper[i]);
        const Eigen::Vector3d rv = F.transpose() * a;
        r = Eigen::Quaterniond(Eigen::AngleAxisd(rv.norm(), rv.normalized()));
        float* c = &clamped[4 * std::size_t(calf)];
        c[0] = float(r.x()), c[1] = float(r.y()), c[2] = float(r.z()), c[3] = float(r.w());
    }
    const std::vector<float> after_clamp = test::posed(m.get(), b.get());
    REQUIRE(ssc_body_set_pose_limited(b.get(), clamped.data(), uint32_t(q.size() / 4), nullptr, SSC_LIMITS_REJECT, &violations) == SSC_OK);
    CHECK(violations == 0);
    const std::vector<float> again = test::posed(m.get(), b.get());
    for (std::size_t i = 0; i < again.size(); ++i) REQUIRE(again[i] == Approx(after_clamp[i]).margin(1e-5));

    // Every named pose passes the limits; bad input is refused.
    for (uint32_t p = 0; p < ssc_named_pose_count(); ++p) {
        const char* name = nullptr;
        REQUIRE(ssc_named_pose_get_info(p, &name, nullptr) == SSC_OK);
        REQUIRE(ssc_model_get_named_pose(m.get(), name, q.data(), uint32_t(q.size() / 4)) == SSC_OK);
        CHECK(ssc_body_set_pose_limited(b.get(), q.data(), uint32_t(q.size() / 4), nullptr, SSC_LIMITS_REJECT, &violations) == SSC_OK);
        CHECK(violations == 0);
    }
    CHECK(ssc_body_set_pose_limited(b.get(), nullptr, 0, nullptr, SSC_LIMITS_CLAMP, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_pose_limited(b.get(), q.data(), 3, nullptr, SSC_LIMITS_CLAMP, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_pose_limited(b.get(), q.data(), uint32_t(q.size() / 4), nullptr, ssc_limit_mode(7), nullptr) ==
          SSC_ERROR_INVALID_ARGUMENT);
    q[1] = std::numeric_limits<float>::quiet_NaN();
    CHECK(ssc_body_set_pose_limited(b.get(), q.data(), uint32_t(q.size() / 4), nullptr, SSC_LIMITS_CLAMP, nullptr) ==
          SSC_ERROR_INVALID_ARGUMENT);
}

TEST_CASE("semantic sliders move one quantity and keep the others", "[semantics][sliders]") {
    const auto m = test::default_model();
    REQUIRE(m);
    const auto b = test::body(m.get());
    const uint32_t S = ssc_model_slider_count(m.get());
    REQUIRE(S >= 6);
    std::vector<std::string> names;
    for (uint32_t i = 0; i < S; ++i) {
        ssc_slider_info info{};
        info.struct_size = sizeof info;
        REQUIRE(ssc_model_get_slider_info(m.get(), i, &info) == SSC_OK);
        CHECK(info.minimum < info.mean);
        CHECK(info.mean < info.maximum);
        CHECK(std::strlen(info.description) > 5);
        names.push_back(info.name);
    }
    for (const char* n : {"stature", "mass", "age", "sex", "muscle"}) CHECK(std::find(names.begin(), names.end(), n) != names.end());
    uint32_t idx = 0;
    CHECK(ssc_model_find_slider(m.get(), "shoe_size", &idx) == SSC_ERROR_NOT_FOUND);
    ssc_slider_info small{};
    small.struct_size = 2;
    CHECK(ssc_model_get_slider_info(m.get(), 0, &small) == SSC_ERROR_INVALID_ARGUMENT);

    // The mean body reads back the population means.
    std::vector<float> v(S), w(S);
    REQUIRE(ssc_body_get_sliders(b.get(), v.data(), S) == SSC_OK);
    for (uint32_t i = 0; i < S; ++i) {
        ssc_slider_info info{};
        info.struct_size = sizeof info;
        REQUIRE(ssc_model_get_slider_info(m.get(), i, &info) == SSC_OK);
        CHECK(v[i] == Approx(info.mean).margin(1e-4));
    }
    // 10 cm taller: the stature slider reads +0.1, the others stay; the body measures about 10 cm taller.
    const uint32_t st = slider(m.get(), "stature"), ma = slider(m.get(), "mass");
    const std::vector<float> m0 = measure_all(b.get());
    REQUIRE(ssc_body_set_slider(b.get(), st, v[st] + 0.1f) == SSC_OK);
    REQUIRE(ssc_body_get_sliders(b.get(), w.data(), S) == SSC_OK);
    for (uint32_t i = 0; i < S; ++i) CHECK(w[i] == Approx(i == st ? v[i] + 0.1f : v[i]).margin(1e-3));
    const std::vector<float> m1 = measure_all(b.get());
    CHECK(m1[SSC_MEASUREMENT_STATURE] - m0[SSC_MEASUREMENT_STATURE] == Approx(0.1).margin(0.015));
    CHECK(std::abs(m1[SSC_MEASUREMENT_MASS] - m0[SSC_MEASUREMENT_MASS]) < 2.5f);  // mass held
    // 10 kg heavier at the same stature.
    REQUIRE(ssc_body_set_slider(b.get(), ma, w[ma] + 10.f) == SSC_OK);
    const std::vector<float> m2 = measure_all(b.get());
    CHECK(m2[SSC_MEASUREMENT_MASS] - m1[SSC_MEASUREMENT_MASS] == Approx(10).margin(2.0));
    CHECK(m2[SSC_MEASUREMENT_STATURE] == Approx(m1[SSC_MEASUREMENT_STATURE]).margin(0.015));
    CHECK(m2[SSC_MEASUREMENT_WAIST_GIRTH] > m1[SSC_MEASUREMENT_WAIST_GIRTH] + 0.03f);

    // All sliders at once: a shape made by sliders reads back exactly; sex changes the body.
    std::vector<float> set = v;
    set[slider(m.get(), "sex")] = 0.f;
    REQUIRE(ssc_body_set_sliders(b.get(), set.data(), S) == SSC_OK);
    REQUIRE(ssc_body_get_sliders(b.get(), w.data(), S) == SSC_OK);
    for (uint32_t i = 0; i < S; ++i) CHECK(w[i] == Approx(set[i]).margin(1e-3));
    const std::vector<float> woman = measure_all(b.get());
    set[slider(m.get(), "sex")] = 1.f;
    REQUIRE(ssc_body_set_sliders(b.get(), set.data(), S) == SSC_OK);
    const std::vector<float> man = measure_all(b.get());
    CHECK(man[SSC_MEASUREMENT_SHOULDER_BREADTH] > woman[SSC_MEASUREMENT_SHOULDER_BREADTH] + 0.01f);
    CHECK(man[SSC_MEASUREMENT_STATURE] == Approx(woman[SSC_MEASUREMENT_STATURE]).margin(0.015));  // stature held

    // Bad input changes nothing.
    std::vector<float> shape(ssc_model_shape_count(m.get())), shape2(shape.size());
    REQUIRE(ssc_body_get_shape(b.get(), shape.data(), uint32_t(shape.size())) == SSC_OK);
    CHECK(ssc_body_set_slider(b.get(), S, 1.f) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_slider(b.get(), st, std::numeric_limits<float>::infinity()) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_set_sliders(b.get(), set.data(), S - 1) == SSC_ERROR_INVALID_ARGUMENT);
    set[0] = std::numeric_limits<float>::quiet_NaN();
    CHECK(ssc_body_set_sliders(b.get(), set.data(), S) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_get_sliders(b.get(), w.data(), S - 1) == SSC_ERROR_BUFFER_TOO_SMALL);
    REQUIRE(ssc_body_get_shape(b.get(), shape2.data(), uint32_t(shape2.size())) == SSC_OK);
    CHECK(shape == shape2);
}

TEST_CASE("bodies made to measure reach the requested measurements", "[semantics][made_to_measure]") {
    const auto m = test::default_model();
    REQUIRE(m);
    const auto b = test::body(m.get()), probe = test::body(m.get());
    const uint32_t K = ssc_model_shape_count(m.get()), M = ssc_measurement_count();
    std::mt19937 rng(11);
    std::normal_distribution<float> n01;
    const uint32_t wanted[4] = {SSC_MEASUREMENT_STATURE, SSC_MEASUREMENT_CHEST_GIRTH, SSC_MEASUREMENT_WAIST_GIRTH,
                                SSC_MEASUREMENT_HIP_GIRTH};
    for (int trial = 0; trial < 3; ++trial) {
        // Targets: the measurements of a random body of the model.
        std::vector<float> c(K);
        for (auto& x : c) x = 0.8f * n01(rng);
        REQUIRE(ssc_body_set_shape(probe.get(), c.data(), K) == SSC_OK);
        const std::vector<float> truth = measure_all(probe.get());
        float values[4];
        for (int i = 0; i < 4; ++i) values[i] = truth[wanted[i]];
        std::vector<float> achieved(M);
        uint32_t converged = 0;
        REQUIRE(ssc_body_make_to_measure(b.get(), wanted, values, 4, nullptr, achieved.data(), M, &converged) == SSC_OK);
        CHECK(converged == 1);
        const std::vector<float> check = measure_all(b.get());
        for (int i = 0; i < 4; ++i) {
            CHECK(achieved[wanted[i]] == Approx(check[wanted[i]]).margin(1e-5));  // reported = measured
            CHECK(std::abs(check[wanted[i]] - values[i]) < 0.002f);
        }
    }
    // A request stated as a customer would give it, with sex and age.
    ssc_made_to_measure_def def;
    ssc_made_to_measure_def_init(&def, sizeof def);
    CHECK(std::isnan(def.sex));
    def.sex = 1.f;
    def.age = 35.f;
    const uint32_t two[2] = {SSC_MEASUREMENT_STATURE, SSC_MEASUREMENT_WAIST_GIRTH};
    const float tall[2] = {1.86f, 0.84f};
    uint32_t converged = 0;
    REQUIRE(ssc_body_make_to_measure(b.get(), two, tall, 2, &def, nullptr, 0, &converged) == SSC_OK);
    CHECK(converged == 1);
    const std::vector<float> got = measure_all(b.get());
    CHECK(got[SSC_MEASUREMENT_STATURE] == Approx(1.86).margin(0.002));
    CHECK(got[SSC_MEASUREMENT_WAIST_GIRTH] == Approx(0.84).margin(0.002));

    // Bad requests leave the body as it was.
    std::vector<float> shape(K), shape2(K);
    REQUIRE(ssc_body_get_shape(b.get(), shape.data(), K) == SSC_OK);
    const uint32_t dup[2] = {SSC_MEASUREMENT_STATURE, SSC_MEASUREMENT_STATURE};
    const uint32_t unknown[1] = {M};
    const float nan[2] = {std::numeric_limits<float>::quiet_NaN(), 1.f}, negative[1] = {-1.f};
    std::vector<float> small(M - 1);
    CHECK(ssc_body_make_to_measure(b.get(), dup, tall, 2, nullptr, nullptr, 0, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_make_to_measure(b.get(), unknown, tall, 1, nullptr, nullptr, 0, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_make_to_measure(b.get(), two, nan, 2, nullptr, nullptr, 0, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_make_to_measure(b.get(), two, negative, 1, nullptr, nullptr, 0, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_make_to_measure(b.get(), two, tall, 0, nullptr, nullptr, 0, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_make_to_measure(b.get(), two, tall, 2, nullptr, small.data(), M - 1, nullptr) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_body_make_to_measure(b.get(), nullptr, tall, 2, nullptr, nullptr, 0, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    def.sex = 3.f;
    CHECK(ssc_body_make_to_measure(b.get(), two, tall, 2, &def, nullptr, 0, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    REQUIRE(ssc_body_get_shape(b.get(), shape2.data(), K) == SSC_OK);
    CHECK(shape == shape2);
}

TEST_CASE("a model without attributes or landmarks has no sliders and says why it cannot make to measure", "[semantics]") {
    const auto m = test::load(test::mini_bytes());
    REQUIRE(m);
    const auto b = test::body(m.get());
    CHECK(ssc_model_slider_count(m.get()) == 0);
    CHECK(ssc_body_set_sliders(b.get(), nullptr, 0) == SSC_OK);
    CHECK(ssc_body_get_sliders(b.get(), nullptr, 0) == SSC_OK);
    const uint32_t st = SSC_MEASUREMENT_STATURE;
    const float v = 1.7f;
    CHECK(ssc_body_make_to_measure(b.get(), &st, &v, 1, nullptr, nullptr, 0, nullptr) == SSC_ERROR_NOT_FOUND);
    ssc_joint_limit l{};
    REQUIRE(ssc_model_get_joint_limit(m.get(), 1, &l) == SSC_OK);
    CHECK(l.limited == 0);
}

TEST_CASE("the attribute model's conditional mean reproduces the population regression", "[semantics]") {
    // Two attributes and two coefficients with known covariances: E[c | a] = C_ca C_aa^-1 (a - mean).
    ssc::format::ModelData d = test::mini_model().data;
    REQUIRE(d.component_count() == 4);
    d.attributes.attributes = {{"height", "m", "h", 1.7f, 1.5f, 1.9f, true}, {"girth", "m", "g", 0.9f, 0.7f, 1.1f, true}};
    d.attributes.covariance = {0.01f, 0.004f, 0.004f, 0.02f};
    d.attributes.shape_covariance = {0.08f, 0.f, 0.01f, 0.f, 0.f, 0.1f, 0.f, 0.f};
    const ssc::semantics::AttributeModel am(d);
    Eigen::Matrix2d caa;
    caa << 0.01, 0.004, 0.004, 0.02;
    Eigen::Matrix<double, 4, 2> cca;
    cca << 0.08, 0, 0, 0.1, 0.01, 0, 0, 0;
    const Eigen::Vector2d a(1.8, 0.85);
    const Eigen::Vector4d expected = cca * caa.inverse() * (a - Eigen::Vector2d(1.7, 0.9));
    const Eigen::VectorXd c = am.conditional_shape({{0, 1.8}, {1, 0.85}});
    for (int k = 0; k < 4; ++k) CHECK(c(k) == Approx(expected(k)).margin(2e-3 * expected.norm()));  // within the ridge
    // Sliders: shape from values reads back the values (R D = I).
    const Eigen::VectorXd back = am.shape_to_sliders(am.sliders_to_shape(a));
    CHECK(back(0) == Approx(1.8).margin(1e-9));
    CHECK(back(1) == Approx(0.85).margin(1e-9));
    CHECK(am.find("girth") == 1);
    CHECK(am.find("weight") == -1);
}
