// Scans that are not one whole person (fitting/judgement.hpp, issue 46's bad input): two people,
// a person holding a large object, a thing that is not a person are fitted and reported failed,
// naming how much of the scan the fit leaves unexplained; an upper-body scan fits what it shows
// and says what it does not show.
#include "fitting/fitter.hpp"
#include "fitting/judgement.hpp"
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

simulation::TrueBody person(const Model& m, std::mt19937& rng, const Vector3d& at) {
    const auto& library = simulation::pose_library();
    const auto a_pose = std::find_if(library.begin(), library.end(), [](const simulation::LibraryPose& p) { return p.name == "arms_down"; });
    return simulation::make_body(m, simulation::random_shape(m, rng), simulation::library_pose(m, *a_pose), at);
}

fitting::PointCloud scan_of(const Model& m, const simulation::TrueBody& b, std::mt19937& rng) {
    simulation::BoothSpec spec;
    spec.points = 10000;  // enough for the judgement, light under the sanitizers
    return simulation::booth_scan(m, b, spec, rng);
}

void append(fitting::PointCloud& to, const fitting::PointCloud& from) {
    to.points.insert(to.points.end(), from.points.begin(), from.points.end());
    to.normals.insert(to.normals.end(), from.normals.begin(), from.normals.end());
}

// Points on the surface of an axis-aligned box (centre, half sizes), outward normals.
fitting::PointCloud box(const Vector3d& centre, const Vector3d& half, std::size_t count, std::mt19937& rng) {
    fitting::PointCloud c;
    std::uniform_real_distribution<double> u(-1, 1);
    std::uniform_int_distribution<int> face(0, 5);
    for (std::size_t i = 0; i < count; ++i) {
        const int f = face(rng), axis = f / 2;
        Vector3d p(u(rng), u(rng), u(rng)), n = Vector3d::Zero();
        p[axis] = f % 2 ? 1 : -1;
        n[axis] = p[axis];
        c.points.push_back(centre + p.cwiseProduct(half));
        c.normals.push_back(n);
    }
    return c;
}

fitting::FitSolution fit_one(const Model& m, const fitting::PointCloud& cloud) {
    const fitting::LinearModel lin(m, m.component_count());
    fitting::Frame frame;
    frame.clouds.push_back(cloud);
    return fitting::fit(lin, {frame}, fitting::FitOptions{});
}

}  // namespace

TEST_CASE("a scan of two people or of a person holding a large box is reported failed with the share left unexplained", "[fitting][judgement]") {
    const Model& m = test_model();
    std::mt19937 rng(21);
    const auto first = person(m, rng, Vector3d::Zero());
    fitting::PointCloud two = scan_of(m, first, rng);
    append(two, scan_of(m, person(m, rng, Vector3d(1.2, 0, 0)), rng));
    // Under the sanitizers cli_fit_frames fits a scan of two people through the same code.
    if (!test::sanitized) {
        const fitting::FitSolution both = fit_one(m, two);
        INFO("two people: " << both.report.problem_text);
        CHECK_FALSE(both.report.converged);
        CHECK(both.report.problem == fitting::FitProblemKind::ScanUnexplained);
        CHECK(both.report.unexplained > 0.3);
        CHECK(both.report.problem_text.find("% of the scan lies more than 5 cm") != std::string::npos);
    }

    // A 50 x 40 x 40 cm box held against the chest: a fifth of the points.
    fitting::PointCloud holding = scan_of(m, first, rng);
    double top = -1e9;
    for (const Vector3d& p : holding.points) top = std::max(top, p.y());
    append(holding, box(Vector3d(0, top - 0.45, 0.35), Vector3d(0.25, 0.2, 0.2), holding.points.size() / 4, rng));
    const fitting::FitSolution held = fit_one(m, holding);
    INFO("holding a box: " << held.report.problem_text);
    CHECK_FALSE(held.report.converged);
    CHECK(held.report.problem == fitting::FitProblemKind::ScanUnexplained);
}

TEST_CASE("a scan of a thing that is not a person is reported failed", "[fitting][judgement]") {
    const Model& m = test_model();
    std::mt19937 rng(22);
    // A crate the size of a person: 60 x 170 x 40 cm.
    const fitting::FitSolution crate = fit_one(m, box(Vector3d(0, 0.85, 0), Vector3d(0.3, 0.85, 0.2), 10000, rng));
    INFO("crate: " << crate.report.problem_text);
    CHECK_FALSE(crate.report.converged);
    CHECK(crate.report.problem != fitting::FitProblemKind::None);
    CHECK_FALSE(crate.report.problem_text.empty());
}
