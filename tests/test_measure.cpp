// Body measurements: tape girths of known shapes, consistency under scaling, plausible values on
// the default model, and the C API's handling of bad input.
#include "capi/handles.hpp"
#include "measure/girth.hpp"
#include "measure/measurements.hpp"
#include "testing/simulated_collection.hpp"
#include "measure/mesh_body.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>

using namespace ssc;
using Eigen::Vector3d;

namespace {

// A closed tube along y: `sides` vertices per ring around (cx, cz), rings at y = 0 and y = 1.
void add_tube(std::vector<float>& xyz, std::vector<uint32_t>& tris, double cx, double cz, double r, int sides) {
    const uint32_t base = uint32_t(xyz.size() / 3);
    for (int ring = 0; ring < 2; ++ring)
        for (int i = 0; i < sides; ++i) {
            const double a = 2 * M_PI * i / sides;
            xyz.insert(xyz.end(), {float(cx + r * std::cos(a)), float(ring), float(cz + r * std::sin(a))});
        }
    for (int i = 0; i < sides; ++i) {
        const uint32_t a = base + uint32_t(i), b = base + uint32_t((i + 1) % sides);
        tris.insert(tris.end(), {a, b, a + uint32_t(sides), b, b + uint32_t(sides), a + uint32_t(sides)});
    }
}


}  // namespace

TEST_CASE("a tape girth is the perimeter of the section's convex hull", "[measure]") {
    std::vector<float> xyz;
    std::vector<uint32_t> tris;
    const int sides = 360;
    add_tube(xyz, tris, 0, 0, 0.1, sides);
    const measure::Plane plane{Vector3d(0, 0.5, 0), Vector3d::UnitY()};
    auto edges = measure::mesh_edges(tris.data(), tris.size() / 3, {});
    REQUIRE(edges.size() == 2 * 4 * std::size_t(sides));  // two rings, risers and diagonals, each once
    const auto one = measure::plane_section(xyz.data(), edges, plane);
    const double polygon = 2 * sides * 0.1 * std::sin(M_PI / sides);  // inscribed polygon's perimeter
    CHECK(measure::tape_girth(one, plane) == Approx(polygon).epsilon(1e-6));
    // Two legs side by side: the tape spans the gap, 2 pi r + twice the distance between centres.
    add_tube(xyz, tris, 0.3, 0, 0.1, sides);
    edges = measure::mesh_edges(tris.data(), tris.size() / 3, {});
    std::vector<Vector3d> hull;
    const auto two = measure::plane_section(xyz.data(), edges, plane);
    CHECK(measure::tape_girth(two, plane, &hull) == Approx(polygon + 0.6).epsilon(1e-4));
    CHECK(hull.size() >= 3);
    // A radius limit keeps one tube; a tilted plane cuts an ellipse, longer than the circle.
    CHECK(measure::tape_girth(measure::plane_section(xyz.data(), edges, plane, 0.15), plane) ==
          Approx(polygon).epsilon(1e-6));
    const measure::Plane tilted{Vector3d(0, 0.5, 0), Vector3d(0.3, 1, 0).normalized()};
    const double ellipse = measure::tape_girth(measure::plane_section(xyz.data(), edges, tilted, 0.2), tilted);
    CHECK(ellipse > polygon * 1.01);
    // An allowed mask that leaves out the second tube.
    std::vector<uint8_t> first(xyz.size() / 3, 0);
    std::fill(first.begin(), first.begin() + 2 * sides, 1);
    const auto first_edges = measure::mesh_edges(tris.data(), tris.size() / 3, first);
    CHECK(measure::tape_girth(measure::plane_section(xyz.data(), first_edges, plane), plane) ==
          Approx(polygon).epsilon(1e-6));
}

TEST_CASE("a multi-level sweep cuts the same sections as one plane at a time", "[measure]") {
    std::vector<float> xyz;
    std::vector<uint32_t> tris;
    add_tube(xyz, tris, 0, 0, 0.1, 40);
    add_tube(xyz, tris, 0.3, 0, 0.05, 40);
    for (std::size_t i = 1; i < xyz.size(); i += 3) xyz[i] = xyz[i] * 0.7f + float(0.05 * std::sin(double(i)));  // uneven rings
    const auto edges = measure::mesh_edges(tris.data(), tris.size() / 3, {});
    const auto levels = measure::horizontal_sections(xyz.data(), edges, 0.9, 0.013, 80);
    REQUIRE(levels.size() == 80);
    std::size_t cut = 0;
    for (int i = 0; i < 80; ++i) {
        const auto one = measure::plane_section(xyz.data(), edges, measure::horizontal_plane(0.9 - i * 0.013));
        REQUIRE(levels[std::size_t(i)].size() == one.size());
        for (std::size_t k = 0; k < one.size(); ++k) CHECK((levels[std::size_t(i)][k] - one[k]).norm() < 1e-12);
        cut += one.size();
    }
    CHECK(cut > 0);
}

TEST_CASE("measurements of the default model are plausible and scale like lengths, areas and volumes", "[measure]") {
    test::DefaultBody b;
    const Model& model = b.model->model;
    const measure::Measurer measurer(model);
    const auto& defs = measure::definitions();
    REQUIRE(defs.size() == ssc_measurement_count());
    auto value = [&](const std::vector<double>& v, const char* name) {
        const int i = measure::find_measurement(name);
        REQUIRE(i >= 0);
        return v[std::size_t(i)];
    };
    std::vector<measure::Path> paths;
    const auto mean = measurer.measure(b.body->body, &paths);
    // Measuring a subset gives the same values for it (the rest left 0).
    for (const char* name : {"hip_girth", "underbust_girth", "calf_girth", "mass", "stature"}) {
        std::vector<bool> only(defs.size(), false);
        only[std::size_t(measure::find_measurement(name))] = true;
        const auto some = measurer.measure(b.body->body, nullptr, &only);
        CHECK(value(some, name) == value(mean, name));
    }
    {
        std::vector<bool> only(defs.size(), false);
        only[std::size_t(measure::find_measurement("stature"))] = true;
        CHECK(value(measurer.measure(b.body->body, nullptr, &only), "hip_girth") == 0.0);
    }
    REQUIRE(paths.size() == defs.size());
    // Adult ranges (metres, m^2, m^3, kg): loose, but each catches a wrong plane or part.
    CHECK(value(mean, "stature") == Approx(1.67).margin(0.1));
    CHECK(value(mean, "chest_girth") > 0.80);
    CHECK(value(mean, "chest_girth") < 1.10);
    CHECK(value(mean, "underbust_girth") < value(mean, "chest_girth"));
    CHECK(value(mean, "waist_girth") < value(mean, "hip_girth"));
    CHECK(value(mean, "hip_girth") > 0.85);
    CHECK(value(mean, "neck_girth") > 0.28);
    CHECK(value(mean, "neck_girth") < 0.45);
    CHECK(value(mean, "thigh_girth") > value(mean, "calf_girth"));
    CHECK(value(mean, "calf_girth") > value(mean, "wrist_girth"));
    CHECK(value(mean, "upper_arm_girth") > value(mean, "wrist_girth"));
    CHECK(value(mean, "wrist_girth") > 0.12);
    CHECK(value(mean, "inseam") > 0.40 * value(mean, "stature"));
    CHECK(value(mean, "inseam") < 0.52 * value(mean, "stature"));
    CHECK(value(mean, "shoulder_breadth") > 0.30);
    CHECK(value(mean, "surface_area") == Approx(1.75).margin(0.3));
    CHECK(value(mean, "mass") == Approx(value(mean, "volume") * measure::kBodyDensity));
    CHECK(value(mean, "mass") > 45);
    CHECK(value(mean, "mass") < 100);
    for (std::size_t m = 0; m < paths.size(); ++m) {
        INFO(defs[m].name);
        if (defs[m].unit == measure::Unit::Metre) CHECK(paths[m].points.size() >= 2);
    }

    // The same body scaled by 1.1 about a point: lengths x1.1, area x1.21, volume and mass x1.331.
    const uint32_t V = model.vertex_count(), J = model.joint_count();
    std::vector<float> xyz(3ull * V), joints(b.body->body.rest_joints(), b.body->body.rest_joints() + 3 * J);
    REQUIRE(ssc_body_get_rest_vertices(b.body, xyz.data(), V, 0) == SSC_OK);
    const auto same = measurer.measure(xyz.data(), joints.data());
    for (std::size_t m = 0; m < mean.size(); ++m) CHECK(same[m] == Approx(mean[m]).epsilon(1e-9));
    const float c[3] = {0.1f, 0.9f, -0.05f};
    for (std::size_t i = 0; i < xyz.size(); ++i) xyz[i] = c[i % 3] + 1.1f * (xyz[i] - c[i % 3]);
    for (std::size_t i = 0; i < joints.size(); ++i) joints[i] = c[i % 3] + 1.1f * (joints[i] - c[i % 3]);
    const auto scaled = measurer.measure(xyz.data(), joints.data());
    for (std::size_t m = 0; m < mean.size(); ++m) {
        INFO(defs[m].name);
        const double factor = defs[m].unit == measure::Unit::Metre ? 1.1 : defs[m].unit == measure::Unit::SquareMetre ? 1.21 : 1.331;
        CHECK(scaled[m] == Approx(factor * mean[m]).epsilon(0.01));
    }
}

TEST_CASE("different shapes measure differently and the pose does not matter", "[measure]") {
    test::DefaultBody b;
    const uint32_t M = ssc_measurement_count();
    std::vector<float> mean(M), other(M), posed(M);
    REQUIRE(ssc_body_measure(b.body, mean.data(), M) == SSC_OK);
    const float shape[3] = {2.0f, -1.5f, 1.0f};
    REQUIRE(ssc_body_set_shape(b.body, shape, 3) == SSC_OK);
    REQUIRE(ssc_body_measure(b.body, other.data(), M) == SSC_OK);
    int differ = 0;
    for (uint32_t m = 0; m < M; ++m) differ += std::abs(other[m] - mean[m]) > 1e-3f * std::abs(mean[m]);
    CHECK(differ >= int(M) - 2);
    std::vector<float> aa(3ull * ssc_model_joint_count(b.model), 0.f);
    uint32_t elbow = 0;
    REQUIRE(ssc_model_find_joint(b.model, "lowerarm_r", &elbow) == SSC_OK);
    aa[3 * elbow] = 1.0f;
    REQUIRE(ssc_body_set_pose_axis_angle(b.body, aa.data(), uint32_t(aa.size() / 3), nullptr) == SSC_OK);
    REQUIRE(ssc_body_measure(b.body, posed.data(), M) == SSC_OK);
    for (uint32_t m = 0; m < M; ++m) CHECK(posed[m] == other[m]);
    float waist = 0;
    REQUIRE(ssc_body_measure_by_name(b.body, "waist_girth", &waist) == SSC_OK);
    CHECK(waist == other[SSC_MEASUREMENT_WAIST_GIRTH]);
}

TEST_CASE("the measurement API rejects bad input without writing", "[measure][capi]") {
    test::DefaultBody b;
    const uint32_t M = ssc_measurement_count();
    std::vector<float> out(M + 1, -7.f);
    CHECK(ssc_body_measure(b.body, out.data(), M - 1) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_body_measure(nullptr, out.data(), M) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_measure(b.body, nullptr, M) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_measure_by_name(b.body, "waist", out.data()) == SSC_ERROR_NOT_FOUND);
    CHECK(std::string(ssc_last_error()).find("waist") != std::string::npos);
    CHECK(ssc_body_measure_by_name(b.body, nullptr, out.data()) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_body_measure_by_name(b.body, "stature", nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    for (float v : out) CHECK(v == -7.f);

    const char* name = nullptr;
    const char* definition = nullptr;
    ssc_unit unit = SSC_UNIT_FORCE32;
    CHECK(ssc_measurement_get_info(M, &name, &unit, &definition) == SSC_ERROR_INVALID_ARGUMENT);
    REQUIRE(ssc_measurement_get_info(SSC_MEASUREMENT_VOLUME, &name, &unit, &definition) == SSC_OK);
    CHECK(std::string(name) == "volume");
    CHECK(unit == SSC_UNIT_CUBIC_METRE);
    CHECK(std::strlen(definition) > 20);
    CHECK(ssc_measurement_get_info(SSC_MEASUREMENT_MASS, nullptr, nullptr, nullptr) == SSC_OK);
    uint32_t index = 99;
    REQUIRE(ssc_measurement_find("hip_girth", &index) == SSC_OK);
    CHECK(index == SSC_MEASUREMENT_HIP_GIRTH);
    CHECK(ssc_measurement_find("Hip", &index) == SSC_ERROR_NOT_FOUND);
    CHECK(ssc_measurement_find("hip_girth", nullptr) == SSC_ERROR_INVALID_ARGUMENT);

    // A model without the CAESAR landmarks cannot be measured: the message says what is missing.
    const auto bytes = test::mini_bytes();
    ssc_model* mini = nullptr;
    REQUIRE(ssc_model_load_memory(nullptr, bytes.data(), bytes.size(), &mini) == SSC_OK);
    ssc_body* body = nullptr;
    REQUIRE(ssc_body_create(mini, nullptr, &body) == SSC_OK);
    CHECK(ssc_body_measure(body, out.data(), M) == SSC_ERROR_NOT_FOUND);
    CHECK(std::string(ssc_last_error()).find("landmark") != std::string::npos);
    for (float v : out) CHECK(v == -7.f);
    ssc_body_destroy(body);
    ssc_model_release(mini);
}

TEST_CASE("a mesh in the model's topology measures as the body it is, wherever it stands, and says when it is posed", "[measure]") {
    test::DefaultBody b;
    const Model& model = test::default_cpp_model();
    const uint32_t M = ssc_measurement_count(), V = ssc_model_vertex_count(b.model);
    const float shape[3] = {2.0f, -1.5f, 1.0f};
    REQUIRE(ssc_body_set_shape(b.body, shape, 3) == SSC_OK);
    std::vector<float> expected(M), rest(3ull * V);
    REQUIRE(ssc_body_measure(b.body, expected.data(), M) == SSC_OK);
    REQUIRE(ssc_body_get_rest_vertices(b.body, rest.data(), V, 0) == SSC_OK);
    // Turned and moved as a file from another tool may have it.
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.5, Vector3d::UnitY()) * Eigen::AngleAxisd(0.2, Vector3d::UnitX())).toRotationMatrix();
    std::vector<Vector3d> moved(V);
    for (uint32_t v = 0; v < V; ++v) moved[v] = R * Vector3d(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]) + Vector3d(3, -1, 2);
    const measure::MeshBody mesh = measure::mesh_body(model, moved);
    CHECK(mesh.off_shape_space < 1e-3);
    const std::vector<double> got = measure::Measurer(model).measure(mesh.xyz.data(), mesh.joints.data());
    for (uint32_t m = 0; m < M; ++m) CHECK(got[m] == Approx(expected[m]).epsilon(1e-4));

    // Posed (both arms lowered, an elbow bent): measured as it stands, and far from the shape space.
    std::vector<float> aa(3ull * ssc_model_joint_count(b.model), 0.f);
    for (const char* name : {"upperarm_l", "upperarm_r", "lowerarm_r"}) {
        uint32_t j = 0;
        REQUIRE(ssc_model_find_joint(b.model, name, &j) == SSC_OK);
        aa[3 * j + 2] = 0.6f;
    }
    REQUIRE(ssc_body_set_pose_axis_angle(b.body, aa.data(), uint32_t(aa.size() / 3), nullptr) == SSC_OK);
    std::vector<float> posed(3ull * V);
    REQUIRE(ssc_body_get_vertices(b.body, posed.data(), V, 0) == SSC_OK);
    std::vector<Vector3d> posed_mesh(V);
    for (uint32_t v = 0; v < V; ++v) posed_mesh[v] = Vector3d(posed[3 * v], posed[3 * v + 1], posed[3 * v + 2]);
    const double off = measure::mesh_body(model, posed_mesh).off_shape_space;
    INFO("posed: " << off * 1e3 << " mm off the shape space");
    CHECK(off > measure::kFarFromShapeSpace);

    // Not a mesh of the model: refused.
    CHECK_THROWS_AS(measure::mesh_body(model, std::vector<Vector3d>(V - 1, Vector3d::Zero())), Error);
    moved[7].x() = std::nan("");
    CHECK_THROWS_AS(measure::mesh_body(model, moved), Error);
}

TEST_CASE("people the model does not hold lie near its shape space at rest, and farther in a booth's posture", "[measure][makehuman]") {
    const std::string root = test::makehuman_root();
    if (root.empty()) {
        WARN("SKIPPED: ../shared/makehuman not found (set SSCAPE_MAKEHUMAN to its path to run this test)");
        return;
    }
    if (test::sanitized) {  // figures only: mesh_body's paths run under the sanitizers in the test above
        WARN("SKIPPED under the sanitizers: the Release run measures these figures");
        return;
    }
    const Model& model = test::default_cpp_model();
    testing::CollectionSpec cs;
    cs.scans = 4;
    cs.points = 500;
    const std::string folder = "mesh_body_makehuman_test";
    const testing::SimulatedCollection c = testing::simulate_collection(root, model, cs, folder);
    REQUIRE(c.truth.size() == cs.scans);
    for (std::size_t s = 0; s < c.truth.size(); ++s) {
        const double rest = measure::mesh_body(model, c.rest[s]).off_shape_space, posed = measure::mesh_body(model, c.truth[s]).off_shape_space;
        INFO("person " << s << ": " << rest * 1e3 << " mm at rest, " << posed * 1e3 << " mm posed");
        CHECK(rest < measure::kFarFromShapeSpace);
        CHECK(posed > rest);
    }
    std::filesystem::remove_all(folder);
}
