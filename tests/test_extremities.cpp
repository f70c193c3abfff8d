// The far ends of a body on its surface (fitting/extremities.hpp): the scan graph's rules, the
// model's tips, and the labelling of booth scans of the pose library as head, hands and feet.
#include "fitting/extremities.hpp"
#include "fitting/fitter.hpp"
#include "simulation/depth_camera.hpp"
#include "simulation/pose_library.hpp"
#include "simulation/simulate.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace ssc;
using Eigen::Vector3d;

namespace {

const Model& test_model() { return test::default_cpp_model(); }

fitting::ModelTips tips_of(const Model& m) {
    const fitting::LinearModel lin(m, m.component_count());
    std::vector<float> identity(4 * std::size_t(m.joint_count()), 0.0f);
    for (std::size_t j = 0; j < m.joint_count(); ++j) identity[4 * j + 3] = 1;
    const simulation::TrueBody rest = simulation::make_body(m, std::vector<float>(m.component_count(), 0.0f), identity, Vector3d::Zero());
    const auto& triangles = m.data().mesh.triangles;
    return fitting::model_tips(rest.vertices, triangles.data(), triangles.size() / 3, fitting::tip_parts(lin));
}

// A square sheet of points (spacing 1 cm) at height y, normals up or down.
void sheet(double y, double normal, std::vector<Vector3d>& points, std::vector<Vector3d>& normals) {
    for (int i = 0; i < 30; ++i)
        for (int k = 0; k < 30; ++k) points.emplace_back(0.01 * i, y, 0.01 * k), normals.emplace_back(0, normal, 0);
}

}  // namespace

TEST_CASE("the scan graph joins a surface, not two surfaces facing each other, and bridges holes", "[fitting][extremities]") {
    std::vector<Vector3d> points, normals;
    sheet(0, -1, points, normals);    // the underside of one part...
    sheet(0.03, 1, points, normals);  // ...touching the top of another, 3 cm apart
    const fitting::SurfaceGraph touching = fitting::scan_graph(points, normals, 0.025);
    const std::vector<double> d = fitting::geodesic_from(touching, {0});
    // Joined only by the bridge between pieces: across it at one place, not everywhere.
    std::size_t far = 0;
    for (std::size_t n = 0; n < d.size(); ++n)
        if (touching.nodes[n].y() > 0.015)
            far += d[n] > 0.05 + std::abs(touching.nodes[n].x() - touching.nodes[0].x()) + std::abs(touching.nodes[n].z() - touching.nodes[0].z());
    CHECK(far > 0);
    // Without normals the two sheets are one surface: every node a step or two away across.
    const fitting::SurfaceGraph unknown = fitting::scan_graph(points, {}, 0.025);
    const std::vector<double> one = fitting::geodesic_from(unknown, {0});
    for (std::size_t n = 0; n < one.size(); ++n)
        if (unknown.nodes[n].y() > 0.015) CHECK(one[n] < 0.05 + std::abs(unknown.nodes[n].x() - unknown.nodes[0].x()) + std::abs(unknown.nodes[n].z() - unknown.nodes[0].z()));
    // A piece beyond a 10 cm hole is joined by its shortest gap.
    std::vector<Vector3d> apart, none;
    for (int i = 0; i < 20; ++i)
        for (int k = 0; k < 5; ++k) apart.emplace_back(0.01 * i + (i >= 10 ? 0.1 : 0.0), 0, 0.01 * k);
    const fitting::SurfaceGraph bridged = fitting::scan_graph(apart, none, 0.02);
    const std::vector<double> across = fitting::geodesic_from(bridged, {0});
    for (double v : across) CHECK(std::isfinite(v));
    // Too few extremities: no labelling.
    fitting::ScanExtremities three;
    three.points.assign(3, Vector3d::Zero());
    three.geodesic = Eigen::MatrixXd::Ones(3, 3);
    CHECK(fitting::label_extremities(three, tips_of(test_model()), 4).empty());
}

TEST_CASE("the model's tips are the crown, the fingertips and the toes", "[fitting][extremities]") {
    const Model& m = test_model();
    const fitting::ModelTips tips = tips_of(m);
    REQUIRE(tips.valid);
    std::vector<float> identity(4 * std::size_t(m.joint_count()), 0.0f);
    for (std::size_t j = 0; j < m.joint_count(); ++j) identity[4 * j + 3] = 1;
    const simulation::TrueBody rest = simulation::make_body(m, std::vector<float>(m.component_count(), 0.0f), identity, Vector3d::Zero());
    double top = -1e9, bottom = 1e9;
    for (const Vector3d& v : rest.vertices) top = std::max(top, v.y()), bottom = std::min(bottom, v.y());
    const auto at = [&](std::size_t t) { return rest.vertices[tips.vertex[t]]; };
    CHECK(at(0).y() > top - 0.03);  // the crown
    CHECK(at(3).y() < bottom + 0.03);
    CHECK(at(4).y() < bottom + 0.03);
    CHECK(at(3).z() > 0.05);  // the toes, in front of the ankle
    CHECK(at(1).x() > 0.3);   // the model frame's x is the body's left
    CHECK(at(2).x() < -0.3);
    CHECK(at(1).y() < at(0).y() - 0.5);
    // Geodesics: symmetric, zero on the diagonal; the head nearer a hand than the hands are to each
    // other, the feet nearer each other than a hand to a foot.
    CHECK((tips.geodesic - tips.geodesic.transpose()).cwiseAbs().maxCoeff() < 1e-9);
    CHECK(tips.geodesic.diagonal().cwiseAbs().maxCoeff() == 0);
    CHECK(tips.geodesic(0, 1) < tips.geodesic(1, 2));
    CHECK(tips.geodesic(3, 4) < tips.geodesic(1, 3));
}

TEST_CASE("extremities of booth scans in the pose library are labelled head, hands and feet", "[fitting][extremities]") {
    const Model& m = test_model();
    const fitting::ModelTips tips = tips_of(m);
    REQUIRE(tips.valid);
    std::mt19937 rng(3);
    std::size_t right = 0, total = 0;
    std::string wrong;
    const auto& library = simulation::pose_library();
    // Under the sanitizers (which check the code, not the rate) every eighth pose.
    const std::size_t step = test::sanitized ? 8 : 1;
    for (std::size_t i = 0; i < library.size(); i += step) {
        const simulation::LibraryPose& pose = library[i];
        simulation::TrueBody b = simulation::make_body(m, simulation::random_shape(m, rng), simulation::library_pose(m, pose), Vector3d::Zero());
        simulation::transform_body(b, simulation::library_orientation(pose), Vector3d::Zero());
        simulation::BoothSpec spec;
        spec.points = 30000;
        const fitting::PointCloud scan = simulation::booth_scan(m, b, spec, rng);
        const fitting::ScanExtremities ex = fitting::scan_extremities(scan.points, scan.normals, 6);
        // Right when the best labelling or its mirror image puts every tip it labels within 15 cm
        // of the true one (the fit that follows tells the two apart).
        bool ok = false;
        const std::vector<fitting::TipLabelling> labels = fitting::label_extremities(ex, tips, 2);
        CHECK((labels.empty() || labels.size() == 2));  // a labelling and its mirror image, or none costs little enough
        for (const fitting::TipLabelling& l : labels) {
            double worst = 0;
            for (std::size_t t = 0; t < fitting::kTipCount; ++t)
                if (l.extremity[t] >= 0) worst = std::max(worst, (ex.points[std::size_t(l.extremity[t])] - b.vertices[tips.vertex[t]]).norm());
            ok |= worst < 0.15;
        }
        right += ok, ++total;
        if (!ok) wrong += " " + pose.name;
    }
    // Measured: 31 of 48. Wrong are the poses whose hands touch the body (arms crossed, hands on
    // the belly: no extremity there) or that fold it (crouching, touching the toes: shortcuts),
    // which the start templates cover.
    INFO(right << " of " << total << " right; wrong:" << wrong);
    if (!test::sanitized) CHECK(right * 5 >= total * 3);
}

TEST_CASE("a leg out sideways and sitting on the floor with the legs out, which the start templates miss, are fitted from the extremity start", "[fitting][extremities]") {
    // Without the extremity start both end 760 and 820 mm off, reported failed after 2 restarts
    // (as on the pose library benchmark).
    const Model& m = test_model();
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> turn(-M_PI, M_PI);
    const auto& library = simulation::pose_library();
    for (const char* name : {"leg_out_sideways", "sitting_floor_legs_out"}) {
        if (test::sanitized && std::string(name) != "leg_out_sideways") continue;  // one under the sanitizers
        const auto pose = std::find_if(library.begin(), library.end(), [&](const simulation::LibraryPose& p) { return p.name == name; });
        REQUIRE(pose != library.end());
        simulation::TrueBody b = simulation::make_body(m, simulation::random_shape(m, rng), simulation::library_pose(m, *pose), Vector3d::Zero());
        simulation::transform_body(b, Eigen::AngleAxisd(turn(rng), Vector3d::UnitY()).toRotationMatrix() * simulation::library_orientation(*pose),
                                   Vector3d::Zero());
        simulation::BoothSpec spec;
        spec.points = 25000;
        fitting::FitOptions options;
        options.components = m.component_count();
        fitting::Fitter fitter(m, options);
        fitter.add_cloud(0, simulation::booth_scan(m, b, spec, rng));
        const fitting::FitReport& report = fitter.solve();
        const std::vector<Vector3d> fitted = fitter.vertices(0);
        double error = 0;
        for (std::size_t v = 0; v < fitted.size(); ++v) error += (fitted[v] - b.vertices[v]).norm() / double(fitted.size());
        INFO(name << ": " << error * 1000 << " mm, " << report.restarts << " restarts; " << report.problem_text);
        CHECK(report.converged);
        CHECK(error < 0.01);
    }
}
