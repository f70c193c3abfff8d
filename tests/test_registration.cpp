// Scan registration: the non-rigid deformation's energy against finite differences and its exact
// solve against a dense one on a tiny mesh, the block Cholesky, scan rims.
#include "registration/block_cholesky.hpp"
#include "support.hpp"
#include "registration/nonrigid.hpp"
#include "registration/rbf_warp.hpp"
#include "registration/register_scan.hpp"
#include "registration/scan_boundary.hpp"
#include "capi/cpp_access.hpp"
#include "common/error.hpp"
#include "simulation/depth_camera.hpp"
#include "simulation/simulate.hpp"
#include "synthesis/model.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>

#include <random>

using namespace ssc;
using registration::NonrigidSystem;
using Eigen::Vector3d;

namespace {

// A bumpy 4 x 4 grid of vertices (two triangles per cell), about 10 cm across, away from the origin.
struct TinyMesh {
    std::vector<Vector3d> vertices;
    std::vector<uint32_t> triangles;
    TinyMesh() {
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> bump(-0.01, 0.01);
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) vertices.emplace_back(0.3 + 0.03 * x, 1.0 + 0.03 * y, 0.5 + bump(rng));
        for (uint32_t y = 0; y < 3; ++y)
            for (uint32_t x = 0; x < 3; ++x) {
                const uint32_t a = 4 * y + x;
                for (uint32_t i : {a, a + 1, a + 5, a, a + 5, a + 4}) triangles.push_back(i);
            }
    }
};

struct Problem {
    TinyMesh mesh;
    std::vector<registration::TemplatePoint> points;
    std::vector<registration::LandmarkTarget> landmarks;
    std::vector<Vector3d> targets;
    std::vector<double> weights;
    registration::EnergyWeights k{1.0, 0.3, 2.0};
    Problem() {
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> u(-0.02, 0.02);
        for (const Vector3d& v : mesh.vertices) {
            targets.push_back(v + Vector3d(u(rng), u(rng), u(rng)));
            weights.push_back(rng() % 4 == 0 ? 0.0 : 0.5 + u(rng) * 10);
        }
        registration::TemplatePoint on_vertex;
        on_vertex.vertex[0] = 6;
        registration::TemplatePoint on_triangle;
        on_triangle.vertex[0] = 0, on_triangle.vertex[1] = 1, on_triangle.vertex[2] = 5;
        on_triangle.weight[0] = 0.2, on_triangle.weight[1] = 0.3, on_triangle.weight[2] = 0.5;
        points = {on_vertex, on_triangle};
        landmarks = {{on_vertex, mesh.vertices[6] + Vector3d(0.01, 0, 0)}, {on_triangle, Vector3d(0.32, 1.01, 0.49)}};
    }
};

}  // namespace

TEST_CASE("mesh edges are the unique undirected edges of the triangles", "[registration]") {
    const TinyMesh m;
    const auto edges = registration::mesh_edges(m.triangles, 16);
    CHECK(edges.size() == 33);  // 3 x 4 rows, 4 x 3 columns, 9 diagonals
    for (const auto& e : edges) CHECK(e[0] < e[1]);
}

TEST_CASE("the non-rigid energy's gradient matches finite differences", "[registration]") {
    Problem p;
    NonrigidSystem system(p.mesh.vertices, registration::mesh_edges(p.mesh.triangles, 16), {}, p.points, 0.7);
    std::mt19937 rng(9);
    std::normal_distribution<double> n(0, 0.05);
    Eigen::MatrixX3d X = system.identity(), anchor = system.identity();
    for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] += n(rng);
    Eigen::SparseMatrix<double> K;
    Eigen::MatrixX3d R;
    system.assemble(p.k, p.targets, p.weights, p.landmarks, anchor, K, R);
    const Eigen::MatrixX3d gradient = 2 * (K * X - R);
    const double h = 1e-6;
    double worst = 0;
    for (Eigen::Index i = 0; i < X.size(); ++i) {
        Eigen::MatrixX3d a = X, b = X;
        a.data()[i] += h, b.data()[i] -= h;
        const double fd = (system.energy(a, p.k, p.targets, p.weights, p.landmarks, anchor) -
                           system.energy(b, p.k, p.targets, p.weights, p.landmarks, anchor)) / (2 * h);
        worst = std::max(worst, std::abs(fd - gradient.data()[i]) / std::max(1.0, std::abs(fd)));
    }
    INFO("worst relative gradient error " << worst);
    CHECK(worst < 1e-6);
    // The quadratic form is the energy up to a constant.
    const double e0 = system.energy(Eigen::MatrixX3d::Zero(X.rows(), 3), p.k, p.targets, p.weights, p.landmarks, anchor);
    const double quadratic = (X.transpose() * (K * X)).trace() - 2 * (X.transpose() * R).trace();
    CHECK(system.energy(X, p.k, p.targets, p.weights, p.landmarks, anchor) - e0 == Approx(quadratic).epsilon(1e-9));
}

TEST_CASE("the non-rigid solve equals a dense solve and minimises the energy", "[registration]") {
    Problem p;
    NonrigidSystem system(p.mesh.vertices, registration::mesh_edges(p.mesh.triangles, 16), {}, p.points);
    const Eigen::MatrixX3d anchor = system.identity();
    system.factorize(p.k, p.weights, p.landmarks);
    const Eigen::MatrixX3d X = system.solve(p.targets, p.landmarks, anchor);
    Eigen::SparseMatrix<double> K;
    Eigen::MatrixX3d R;
    system.assemble(p.k, p.targets, p.weights, p.landmarks, anchor, K, R);
    const Eigen::MatrixXd dense = Eigen::MatrixXd(K);
    CHECK((dense - dense.transpose()).cwiseAbs().maxCoeff() < 1e-15);
    const Eigen::MatrixX3d reference = dense.ldlt().solve(R);
    CHECK((X - reference).cwiseAbs().maxCoeff() < 1e-9 * std::max(1.0, reference.cwiseAbs().maxCoeff()));
    const double best = system.energy(X, p.k, p.targets, p.weights, p.landmarks, anchor);
    std::mt19937 rng(1);
    std::normal_distribution<double> n(0, 1e-4);
    for (int trial = 0; trial < 20; ++trial) {
        Eigen::MatrixX3d Y = X;
        for (Eigen::Index i = 0; i < Y.size(); ++i) Y.data()[i] += n(rng);
        CHECK(system.energy(Y, p.k, p.targets, p.weights, p.landmarks, anchor) > best);
    }
    // Other targets at the same weights reuse the factorisation; other weights reuse the analysis.
    std::vector<Vector3d> moved_targets = p.targets;
    for (auto& t : moved_targets) t += Vector3d(0.001, -0.002, 0.003);
    const Eigen::MatrixX3d X1 = system.solve(moved_targets, p.landmarks, anchor);
    system.assemble(p.k, moved_targets, p.weights, p.landmarks, anchor, K, R);
    CHECK((X1 - Eigen::MatrixXd(K).ldlt().solve(R)).cwiseAbs().maxCoeff() < 1e-9);
    p.k.stiffness = 0.01;
    system.factorize(p.k, p.weights, p.landmarks);
    const Eigen::MatrixX3d X2 = system.solve(p.targets, p.landmarks, anchor);
    system.assemble(p.k, p.targets, p.weights, p.landmarks, anchor, K, R);
    CHECK((X2 - Eigen::MatrixXd(K).ldlt().solve(R)).cwiseAbs().maxCoeff() < 1e-9);
    // Stiff enough, the deformation is one affine map; without data or landmarks, the template stays.
    std::vector<double> none(p.weights.size(), 0.0);
    system.factorize(p.k, none, {});
    const Eigen::MatrixX3d still = system.solve(p.targets, {}, anchor);
    const auto moved = system.deformed(still);
    for (std::size_t v = 0; v < moved.size(); ++v) CHECK((moved[v] - p.mesh.vertices[v]).norm() < 1e-8);
}

TEST_CASE("the 4x4 block Cholesky solves as a dense factorisation on a random sparse structure", "[registration]") {
    std::mt19937 rng(17);
    std::normal_distribution<double> n(0, 1);
    const int blocks = 40;
    // A random symmetric block structure: a ring plus random chords; each block random, the
    // diagonal made dominant.
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(4 * blocks, 4 * blocks);
    auto couple = [&](int i, int j) {
        Eigen::Matrix4d b;
        for (int k = 0; k < 16; ++k) b.data()[k] = n(rng);
        dense.block<4, 4>(4 * i, 4 * j) += b;
        dense.block<4, 4>(4 * j, 4 * i) += b.transpose();
    };
    for (int i = 0; i < blocks; ++i) couple(i, (i + 1) % blocks);
    for (int c = 0; c < 30; ++c) {
        const int i = int(rng() % blocks), j = int(rng() % blocks);
        if (i != j) couple(i, j);
    }
    for (int i = 0; i < blocks; ++i) {
        Eigen::Matrix4d b;
        for (int k = 0; k < 16; ++k) b.data()[k] = n(rng);
        dense.block<4, 4>(4 * i, 4 * i) += b * b.transpose() + 40 * Eigen::Matrix4d::Identity();
    }
    // Stored with every entry of every nonzero block (zeros included), as NonrigidSystem does.
    std::vector<Eigen::Triplet<double>> t;
    for (int j = 0; j < blocks; ++j)
        for (int i = 0; i < blocks; ++i)
            if (dense.block<4, 4>(4 * i, 4 * j).cwiseAbs().maxCoeff() > 0)
                for (int b = 0; b < 4; ++b)
                    for (int a = 0; a < 4; ++a) t.emplace_back(4 * i + a, 4 * j + b, dense(4 * i + a, 4 * j + b));
    Eigen::SparseMatrix<double> K(4 * blocks, 4 * blocks);
    K.setFromTriplets(t.begin(), t.end());
    K.makeCompressed();
    registration::BlockCholesky4 chol;
    chol.analyze(K);
    REQUIRE(chol.factorize(K));
    Eigen::MatrixX3d B(4 * blocks, 3);
    for (Eigen::Index i = 0; i < B.size(); ++i) B.data()[i] = n(rng);
    const Eigen::MatrixX3d X = chol.solve(B), reference = dense.llt().solve(B);
    CHECK((X - reference).cwiseAbs().maxCoeff() < 1e-10 * std::max(1.0, reference.cwiseAbs().maxCoeff()));
    // The same structure with other values reuses the analysis; an indefinite matrix is refused.
    K *= 2.0;
    REQUIRE(chol.factorize(K));
    CHECK((chol.solve(B) - 0.5 * reference).cwiseAbs().maxCoeff() < 1e-10);
    K *= -1.0;
    CHECK_FALSE(chol.factorize(K));
}

TEST_CASE("the block Cholesky's subtrees on threads give the factor and solution it gives alone", "[registration]") {
    // The default template's deformation system: its elimination tree splits into two
    // independent groups of subtrees. The solve must match Eigen's and not depend on threads.
    test::DefaultBody d;
    const std::vector<float> rest = test::rest(d.model, d.body);
    const uint32_t V = ssc_model_vertex_count(d.model);
    std::vector<Vector3d> vertices(V);
    for (uint32_t v = 0; v < V; ++v) vertices[v] = Vector3d(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]);
    const auto& mesh = test::default_cpp_model().data().mesh;
    const std::vector<uint32_t> triangles(mesh.triangles.begin(), mesh.triangles.end());
    NonrigidSystem system(vertices, registration::mesh_edges(triangles, V), {}, {});
    std::mt19937 rng(5);
    std::normal_distribution<double> n(0, 1);
    std::vector<Vector3d> targets(V);
    std::vector<double> weights(V);
    for (uint32_t v = 0; v < V; ++v) targets[v] = vertices[v] + 0.01 * Vector3d(n(rng), n(rng), n(rng)), weights[v] = rng() % 5 ? 1.0 : 0.0;
    Eigen::SparseMatrix<double> K;
    Eigen::MatrixX3d B;
    system.assemble({1.0, 0.01, 0.0}, targets, weights, {}, system.identity(), K, B);
    const Eigen::MatrixX3d reference = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>(K).solve(B);

    registration::BlockCholesky4 chol;
    chol.analyze(K);
    CHECK(chol.parallel_parts() == 2);
    REQUIRE(chol.factorize(K));
    const Eigen::MatrixX3d alone = chol.solve(B);
    CHECK((K * alone - B).cwiseAbs().maxCoeff() < 1e-9 * B.cwiseAbs().maxCoeff());
    CHECK((alone - reference).cwiseAbs().maxCoeff() < 1e-6 * reference.cwiseAbs().maxCoeff());
    for (const unsigned threads : {2u, 3u}) {
        ThreadPool pool(threads);
        REQUIRE(chol.factorize(K, &pool));
        CHECK(chol.solve(B, &pool) == alone);
        CHECK(chol.solve(B) == alone);
    }
    // A failure on a thread is reported, and the next factorisation starts clean.
    ThreadPool pool(2);
    const Eigen::SparseMatrix<double> negative = -K;
    CHECK_FALSE(chol.factorize(negative, &pool));
    REQUIRE(chol.factorize(K, &pool));
    CHECK(chol.solve(B, &pool) == alone);
}

TEST_CASE("scan boundaries are the rims of holes and of the scan, not its inside", "[registration]") {
    // A 40 x 40 cm patch of random points (about 4 mm apart) with a round hole of 6 cm radius.
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-0.2, 0.2);
    std::vector<Vector3d> points, normals;
    while (points.size() < 8000) {
        const Vector3d p(u(rng), u(rng), 0);
        if (p.norm() < 0.06) continue;
        points.push_back(p);
        normals.emplace_back(0, 0, 1);
    }
    const fitting::PointIndex index(points);
    const registration::ScanRim rim(points, normals, index);
    std::size_t hole_rim = 0, hole_ring = 0, inside = 0, inside_rim = 0, edge = 0, edge_rim = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double r = points[i].norm(), border = 0.2 - std::max(std::abs(points[i].x()), std::abs(points[i].y()));
        if (r < 0.064) ++hole_ring, hole_rim += rim(uint32_t(i));
        else if (border < 0.002) ++edge, edge_rim += rim(uint32_t(i));
        else if (r > 0.08 && border > 0.02) ++inside, inside_rim += rim(uint32_t(i));
    }
    INFO("hole ring " << hole_rim << " of " << hole_ring << ", edge " << edge_rim << " of " << edge << ", inside " << inside_rim << " of " << inside);
    CHECK(hole_rim > 0.7 * double(hole_ring));
    CHECK(edge_rim > 0.7 * double(edge));
    CHECK(inside_rim < 0.01 * double(inside));
    // A mesh's rim: the vertices of edges one triangle uses (two triangles: the four corners).
    const auto mesh_rim = registration::mesh_boundary({0, 1, 2, 0, 2, 3}, 5);
    CHECK(mesh_rim == std::vector<uint8_t>{1, 1, 1, 1, 0});
}

namespace {


// A body the model cannot represent (bumps and dents), mildly posed, scanned: 40,000 points, 1 mm
// noise, a tenth of the surface in holes.
struct BumpyScan {
    simulation::TrueBody truth;
    registration::Scan scan;
    explicit BumpyScan(uint32_t seed, uint32_t points = 40000) {
        const Model& m = test::default_cpp_model();
        std::mt19937 rng(seed);
        truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng, 0.3), Vector3d(0.1, 0, 0.4));
        simulation::add_bumps(truth, m, 8, rng);
        simulation::CloudSpec spec;
        spec.points = points;
        spec.noise = 0.001;
        spec.missing = 0.1;
        spec.outliers = 0;
        scan.cloud = simulation::simulate_cloud(m, truth, spec, rng);
        scan.landmarks = simulation::simulate_landmarks(m, truth, 0.0, true, rng);
    }
};

// Mean distance of the true body's vertices to a mesh of the template's topology (how well its
// shape is matched, whatever its correspondence), over the torso, arms and legs: the head, hands
// and feet hold inner surfaces (mouth, between fingers and toes) that a scan does not show.
double surface_error(const Model& m, const std::vector<Vector3d>& x, const simulation::TrueBody& truth) {
    const std::vector<uint32_t> triangles(m.data().mesh.triangles.begin(), m.data().mesh.triangles.end());
    const fitting::PointIndex index(truth.vertices);
    ThreadPool pool(1);
    const registration::BodyRegions regions = registration::body_regions(m.data());
    const auto q = registration::registration_quality(x, triangles, registration::vertex_normals(x, triangles), regions.of_vertex, regions.names,
                                                      truth.vertices, truth.normals, true, index, pool);
    double sum = 0;
    std::size_t n = 0;
    for (const auto& r : q.regions)
        if (r.region == "torso" || r.region == "arms" || r.region == "legs")
            sum += r.scan_to_registration.mean * double(r.scan_to_registration.count), n += r.scan_to_registration.count;
    return sum / double(n);
}

}  // namespace

TEST_CASE("a scan registers onto the template closer than the model fit that starts it", "[registration]") {
    const Model& m = test::default_cpp_model();
    // With the segment shape spaces (RegistrationOptions::segments, the default), the head's left out.
    const fitting::LinearModel lin(m, m.component_count(), nullptr, true, registration::RegistrationOptions().segments_left_out);
    const BumpyScan s(31);
    registration::Scan without_landmarks = s.scan;
    without_landmarks.landmarks.clear();
    ThreadPool pool(2);
    const registration::Registration r = registration::register_scan(lin, without_landmarks, {}, {}, &pool);
    REQUIRE(r.vertices.size() == m.vertex_count());
    REQUIRE(r.fit.frames[0].shape.size() == m.component_count() + m.segment_coefficient_count());
    double head = 0, others = 0;  // the head is segment 0, its coefficients first
    for (std::size_t k = m.component_count(); k < r.fit.frames[0].shape.size(); ++k)
        (k < m.component_count() + m.segments()[0].components ? head : others) += std::abs(r.fit.frames[0].shape[k]);
    CHECK(head == 0);
    CHECK(others > 0);
    const auto fitted = simulation::fitted_vertices(m, r.fit.frames[0]);
    const double fit_surface = surface_error(m, fitted, s.truth), reg_surface = surface_error(m, r.vertices, s.truth);
    const auto& q = r.report.quality;
    INFO("true surface to fit " << fit_surface * 1e3 << " mm, to registration " << reg_surface * 1e3 << " mm; scan to registration mean "
                                  << q.scan_to_registration.mean * 1e3 << " mm; valid " << r.report.valid);
    CHECK(reg_surface < 0.75 * fit_surface);
    CHECK(reg_surface < 0.001);
    CHECK(q.scan_to_registration.mean < 0.0015);
    CHECK(q.below[1] > 0.5);                        // half the vertices within 5 mm of a scan point
    CHECK(r.report.valid > m.vertex_count() / 2);  // most vertices ended on the scan
    CHECK(q.regions.size() == m.data().vertex_sets.size());
    CHECK(r.report.rounds == 6);  // the stiffness relaxed by 4 until it fell by 1000
}

TEST_CASE("a scan above the point bound is registered from an even subsample and says so", "[registration]") {
    // 10 million points once took 3.4 GB (about 350 bytes a point): RegistrationOptions::max_scan_points
    // (kMaxScanPoints, 2 million by default) bounds what a registration holds.
    const Model& m = test::default_cpp_model();
    const fitting::LinearModel lin(m, m.component_count(), nullptr, true, registration::RegistrationOptions().segments_left_out);
    BumpyScan s(34, 8000);
    s.scan.landmarks.clear();
    registration::RegistrationOptions options;
    options.max_scan_points = 999;
    CHECK_THROWS_WITH(registration::register_scan(lin, s.scan, options), Catch::Contains("max_scan_points must be at least 1000"));
    options.max_scan_points = 2000;
    ThreadPool pool(2);
    const registration::Registration r = registration::register_scan(lin, s.scan, options, {}, &pool);
    CHECK(r.report.scan_points == 2000);
    CHECK(r.report.scan_points_given == 8000);
    CHECK(r.report.quality.scan_to_registration.count == 2000);
    CHECK(r.report.quality.below[3] > 0.5);  // still the person: most of the template within 20 mm
    CHECK(registration::kMaxScanPoints == registration::RegistrationOptions().max_scan_points);
}

TEST_CASE("landmarks given with a scan hold the model fit and the registration to them", "[registration]") {
    // The registration's fit weighs landmarks as if placed to 2 mm (registration_fit()). At the
    // fitter's 1 cm the scan's points outvoted them on this scan: after the fit the landmarks' rms
    // was 5.1 mm and the worst 17.5 mm off (at 2 mm: 3.7 and 12.0).
    const Model& m = test::default_cpp_model();
    const fitting::LinearModel lin(m, m.component_count(), nullptr, true, registration::RegistrationOptions().segments_left_out);
    const BumpyScan s(31);
    REQUIRE(s.scan.landmarks.size() > 50);
    ThreadPool pool(2);
    const registration::Registration r = registration::register_scan(lin, s.scan, {}, {}, &pool);
    // Each landmark's distance on a mesh of the template's topology: mean and worst.
    auto landmark_errors = [&](const std::vector<Vector3d>& x) {
        double sum = 0, worst = 0;
        for (const auto& l : s.scan.landmarks) {
            const fitting::SurfacePoint p = fitting::landmark_point(m.data(), l.landmark);
            Vector3d at = Vector3d::Zero();
            for (int i = 0; i < 3; ++i) at += p.weight[i] * x[p.vertex[i]];
            sum += (at - l.position).norm(), worst = std::max(worst, (at - l.position).norm());
        }
        return std::pair<double, double>(sum / double(s.scan.landmarks.size()), worst);
    };
    const auto fit = landmark_errors(simulation::fitted_vertices(m, r.fit.frames[0])), registered = landmark_errors(r.vertices);
    INFO("landmarks after the fit: mean " << fit.first * 1e3 << " mm, worst " << fit.second * 1e3 << " mm; after the registration: mean "
                                         << registered.first * 1e3 << " mm, worst " << registered.second * 1e3 << " mm; fit's rms "
                                         << r.fit.report.landmark_rms * 1e3 << " mm");
    CHECK(r.fit.report.landmark_rms < 0.0045);
    CHECK(fit.second < 0.015);
    CHECK(registered.first < fit.first);  // the deformation's landmark term brings them closer still
    CHECK(r.report.landmarks == s.scan.landmarks.size());
    // The deformation leaves out the wrists' four (within 3 cm of the hands, which the fit placed).
    std::size_t wrists = 0;
    for (const auto& l : s.scan.landmarks) wrists += m.data().landmarks[l.landmark].name.find("Styloid") != std::string::npos;
    CHECK(wrists == 4);
    CHECK(r.report.deformation_landmarks == s.scan.landmarks.size() - wrists);
}

TEST_CASE("with the segment shape spaces, a fit with an arm astray is restarted before they join", "[registration][segments]") {
    // This scan's first fit puts the right arm off its scan. With the whole body's components it
    // leaves more than 3 % of the scan unexplained and is restarted; the segments, had they
    // joined first, would have taken up enough of the error to hide it (2.5 %, the arm 13 mm off).
    const Model& m = test::default_cpp_model();
    const fitting::LinearModel lin(m, m.component_count(), nullptr, true, registration::RegistrationOptions().segments_left_out);
    const BumpyScan s(33);
    registration::Scan cloud_only;
    for (const auto& p : s.scan.cloud.points) cloud_only.cloud.points.emplace_back(float(p.x()), float(p.y()), float(p.z()));
    registration::RegistrationOptions o;
    o.segments = true;
    const registration::Registration r = registration::register_scan(lin, cloud_only, o);
    CHECK(r.fit.report.restarts > 0);
    CHECK(r.fit.report.unexplained < 0.01);
    for (const auto& q : r.report.quality.regions) {
        INFO(q.region << ": scan to registration " << q.scan_to_registration.mean * 1e3 << " mm");
        if (q.region == "arms" || q.region == "torso" || q.region == "legs") CHECK(q.scan_to_registration.mean < 0.0015);
    }
}

TEST_CASE("registration starts from landmarks alone (rigid, rbf), and refuses what it cannot do", "[registration]") {
    const Model& m = test::default_cpp_model();
    const fitting::LinearModel lin(m, m.component_count());
    const BumpyScan s(32);
    registration::RegistrationOptions rigid;
    rigid.initialisation = registration::Initialisation::Rigid;
    const registration::Registration r = registration::register_scan(lin, s.scan, rigid);
    CHECK(r.fit.frames.empty());
    INFO("rigid start: scan to registration mean " << r.report.quality.scan_to_registration.mean * 1e3 << " mm");
    CHECK(r.report.quality.scan_to_registration.mean < 0.006);  // the weak baseline: the template at rest, placed
    CHECK(r.report.deformation_landmarks == s.scan.landmarks.size());  // every landmark pulls: nothing else places the hands
    auto status = [&](const registration::Scan& scan, const registration::RegistrationOptions& o, const registration::RegistrationProgress& p = {}) {
        try {
            registration::register_scan(lin, scan, o, p);
        } catch (const Error& e) {
            return e.status();
        }
        return SSC_OK;
    };
    registration::Scan no_marks = s.scan;
    no_marks.landmarks.clear();
    CHECK(status(no_marks, rigid) == SSC_ERROR_INVALID_ARGUMENT);  // rigid needs landmarks
    registration::RegistrationOptions rbf;
    rbf.initialisation = registration::Initialisation::Rbf;
    registration::Scan three = s.scan;
    three.landmarks.resize(3);
    CHECK(status(three, rbf) == SSC_ERROR_INVALID_ARGUMENT);  // rbf needs 4 landmarks
    const registration::Registration warped = registration::register_scan(lin, s.scan, rbf);
    INFO("rbf start: scan to registration mean " << warped.report.quality.scan_to_registration.mean * 1e3 << " mm");
    CHECK(warped.report.quality.scan_to_registration.mean < 0.006);
    registration::Scan tiny;
    for (int i = 0; i < 50; ++i) tiny.cloud.points.emplace_back(0.01 * i, 1, 0);
    CHECK(status(tiny, {}) == SSC_ERROR_INVALID_ARGUMENT);
    registration::Scan nan = s.scan;
    nan.cloud.points[7].x() = std::nan("");
    CHECK(status(nan, {}) == SSC_ERROR_INVALID_ARGUMENT);
    registration::RegistrationOptions bad;
    bad.stiffness = -1;
    CHECK(status(s.scan, bad) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(status(s.scan, rigid, [](const char* stage, uint32_t, uint32_t) { return std::string(stage) != "deform"; }) == SSC_ERROR_CANCELLED);
}

TEST_CASE("the C API registers a scan and refuses misuse with a status and a message", "[registration][capi]") {
    ssc_model* model = nullptr;
    REQUIRE(ssc_model_load_default(nullptr, &model) == SSC_OK);
    // Under the sanitizers a sparser scan: the same calls, a third of the minute and a half there.
    const BumpyScan s(33, test::sanitized ? 12000 : 40000);
    ssc_registration* reg = nullptr;
    CHECK(ssc_registration_create(nullptr, nullptr, &reg) == SSC_ERROR_INVALID_ARGUMENT);
    ssc_registration_def def;
    ssc_registration_def_init(&def, sizeof def);
    CHECK(def.stiffness == Approx(0.03f));
    def.stiffness = std::nanf("");
    CHECK(ssc_registration_create(model, &def, &reg) == SSC_ERROR_INVALID_ARGUMENT);
    def.stiffness = 0.1f;
    def.start = static_cast<ssc_registration_start>(7);
    CHECK(ssc_registration_create(model, &def, &reg) == SSC_ERROR_INVALID_ARGUMENT);
    REQUIRE(ssc_registration_create(model, nullptr, &reg) == SSC_OK);
    CHECK(ssc_registration_run(reg, nullptr, nullptr, nullptr) == SSC_ERROR_INVALID_ARGUMENT);  // no scan
    CHECK(std::string(ssc_last_error()).find("no scan") != std::string::npos);
    std::vector<float> pts;
    for (const auto& p : s.scan.cloud.points) pts.insert(pts.end(), {float(p.x()), float(p.y()), float(p.z())});
    const uint32_t n = uint32_t(s.scan.cloud.points.size());
    CHECK(ssc_registration_set_scan(reg, pts.data(), nullptr, 50, 0, nullptr, 0) == SSC_ERROR_INVALID_ARGUMENT);  // too few
    std::vector<float> bad = pts;
    bad[30] = std::nanf("");
    CHECK(ssc_registration_set_scan(reg, bad.data(), nullptr, n, 0, nullptr, 0) == SSC_ERROR_INVALID_ARGUMENT);
    const uint32_t out_of_range[3] = {0, 1, n};
    CHECK(ssc_registration_set_scan(reg, pts.data(), nullptr, n, 0, out_of_range, 1) == SSC_ERROR_INVALID_ARGUMENT);
    const char* names[1] = {"NoSuchLandmark"};
    const float where[3] = {0, 1, 0};
    CHECK(ssc_registration_set_landmarks_by_name(reg, names, where, 1) == SSC_ERROR_NOT_FOUND);
    const char* twice[2] = {"Sellion", "Sellion"};
    const float two_places[6] = {0, 1.6f, 0.1f, 0, 1.3f, 0.1f};
    CHECK(ssc_registration_set_landmarks_by_name(reg, twice, two_places, 2) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(ssc_last_error()).find("twice") != std::string::npos);
    REQUIRE(ssc_registration_set_scan(reg, pts.data(), nullptr, n, 0, nullptr, 0) == SSC_OK);
    const uint32_t V = ssc_model_vertex_count(model);
    std::vector<float> verts(3ull * V);
    CHECK(ssc_registration_get_vertices(reg, verts.data(), V, 0) == SSC_ERROR_INVALID_ARGUMENT);  // not run yet
    CHECK(ssc_registration_region_count(reg) == 0);
    ssc_registration_report report;
    report.struct_size = sizeof report;
    int calls = 0;
    const ssc_stage_progress_fn count = [](void* user, const char*, uint32_t, uint32_t) {
        ++*static_cast<int*>(user);
        return 0;
    };
    REQUIRE(ssc_registration_run(reg, count, &calls, &report) == SSC_OK);
    CHECK(calls > 6);
    CHECK(report.rounds == 6);
    CHECK(report.quality.scan_mean < 0.002f);
    CHECK(ssc_registration_get_vertices(reg, verts.data(), V - 1, 0) == SSC_ERROR_BUFFER_TOO_SMALL);
    REQUIRE(ssc_registration_get_vertices(reg, verts.data(), V, 0) == SSC_OK);
    std::vector<uint8_t> valid(V);
    REQUIRE(ssc_registration_get_valid(reg, valid.data(), V) == SSC_OK);
    uint32_t on_scan = 0;
    for (uint8_t v : valid) on_scan += v;
    CHECK(on_scan == report.valid_vertices);
    std::vector<float> distance(V);
    REQUIRE(ssc_registration_get_vertex_distances(reg, distance.data(), V) == SSC_OK);
    std::vector<float> shape(ssc_model_shape_count(model));
    CHECK(ssc_registration_get_fit(reg, shape.data(), uint32_t(shape.size()), nullptr, 0, nullptr, nullptr) == SSC_OK);
    // The fit's segment shapes: the default fit uses them, but the head's (left out: zero).
    CHECK(def.fit_segments == 1u);
    REQUIRE(ssc_model_segment_count(model) == 6);
    ssc_segment_info info;
    info.struct_size = sizeof info;
    REQUIRE(ssc_model_get_segment_info(model, 1, &info) == SSC_OK);
    std::vector<float> arm(info.shape_count, -99.f);
    double head = 0, others = 0;
    for (uint32_t g = 0; g < 6; ++g) {
        REQUIRE(ssc_registration_get_fit_segment_shape(reg, g, arm.data(), uint32_t(arm.size())) == SSC_OK);
        for (float c : arm) (g == 0 ? head : others) += std::abs(c);
    }
    CHECK(head == 0);
    CHECK(others > 0);
    CHECK(ssc_registration_get_fit_segment_shape(reg, 6, arm.data(), uint32_t(arm.size())) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_registration_get_fit_segment_shape(reg, 1, arm.data(), info.shape_count - 1) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_registration_get_fit_segment_shape(reg, 1, nullptr, info.shape_count) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_registration_get_fit_segment_shape(nullptr, 1, arm.data(), info.shape_count) == SSC_ERROR_INVALID_ARGUMENT);
    REQUIRE(ssc_registration_region_count(reg) == 6);
    const char* region = nullptr;
    ssc_registration_quality q;
    REQUIRE(ssc_registration_get_region(reg, 1, &region, &q) == SSC_OK);
    CHECK(std::string(region) == "torso");
    CHECK(q.within[3] > 0.8f);
    CHECK(ssc_registration_get_region(reg, 6, &region, &q) == SSC_ERROR_INVALID_ARGUMENT);
    // The same as the C++ registration of the same scan (not under the sanitizers: the same code
    // again, a minute there).
    if (!test::sanitized) {
        const registration::RegistrationOptions defaults;
        const fitting::LinearModel lin(test::default_cpp_model(), test::default_cpp_model().component_count(), nullptr, defaults.segments,
                                       defaults.segments_left_out);
        registration::Scan cloud_only;
        for (uint32_t i = 0; i < n; ++i) cloud_only.cloud.points.emplace_back(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]);
        const auto direct = registration::register_scan(lin, cloud_only, {});
        double worst = 0;
        for (uint32_t v = 0; v < V; ++v) worst = std::max(worst, (direct.vertices[v] - Vector3d(verts[3 * v], verts[3 * v + 1], verts[3 * v + 2])).norm());
        CHECK(worst < 1e-5);
    }
    // A cancel leaves no result.
    const ssc_stage_progress_fn stop = [](void*, const char* stage, uint32_t, uint32_t) { return std::string(stage) == "deform" ? 1 : 0; };
    CHECK(ssc_registration_run(reg, stop, nullptr, nullptr) == SSC_ERROR_CANCELLED);
    CHECK(ssc_registration_get_vertices(reg, verts.data(), V, 0) == SSC_ERROR_INVALID_ARGUMENT);
    ssc_registration_destroy(reg);
    ssc_registration_destroy(nullptr);
    ssc_model_release(model);
}

TEST_CASE("the simulator poses other bodies as the model poses its own, and scans them in a booth", "[registration][simulation]") {
    const Model& m = test::default_cpp_model();
    std::mt19937 rng(8);
    const std::vector<float> shape = simulation::random_shape(m, rng), pose = simulation::random_pose(m, rng, 0.5);
    std::vector<float> identity(4 * std::size_t(m.joint_count()), 0.f);
    for (uint32_t j = 0; j < m.joint_count(); ++j) identity[4 * j + 3] = 1.f;
    const auto at_rest = simulation::make_body(m, shape, identity, Vector3d::Zero());
    const auto posed = simulation::make_body(m, shape, pose, Vector3d(0.1, 0.2, 0.3));
    const auto other = simulation::pose_rest_vertices(m, at_rest.vertices, pose, Vector3d(0.1, 0.2, 0.3));
    double worst = 0;
    for (std::size_t v = 0; v < posed.vertices.size(); ++v) worst = std::max(worst, (posed.vertices[v] - other.vertices[v]).norm());
    CHECK(worst < 1e-4);  // the runtime's float synthesis against doubles
    simulation::BoothSpec booth;
    booth.points = 20000;
    const fitting::PointCloud scan = simulation::booth_scan(m, posed, booth, rng);
    REQUIRE(scan.points.size() == 20000);
    // Every point lies on the body (noise 1 mm), and the soles are not seen.
    const std::vector<uint32_t> triangles(m.data().mesh.triangles.begin(), m.data().mesh.triangles.end());
    const fitting::PointIndex index(scan.points);
    ThreadPool pool(1);
    const auto on_body = registration::registration_quality(posed.vertices, triangles, posed.normals, std::vector<int>(posed.vertices.size(), -1),
                                                            {}, scan.points, scan.normals, true, index, pool);
    INFO("scan points to the body: mean " << on_body.scan_to_registration.mean * 1e3 << " mm, p95 " << on_body.scan_to_registration.p95 * 1e3);
    CHECK(on_body.scan_to_registration.mean < 0.0012);
    CHECK(on_body.scan_to_registration.p95 < 0.003);
    double lowest = 1e9;
    for (const auto& v : posed.vertices) lowest = std::min(lowest, v.y());
    std::size_t facing_down = 0;
    for (std::size_t i = 0; i < scan.points.size(); ++i) facing_down += scan.points[i].y() < lowest + 0.01 && scan.normals[i].y() < -0.9;
    CHECK(facing_down == 0);
}

TEST_CASE("the rbf warp passes through its landmarks and keeps affine maps affine", "[registration]") {
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    std::vector<Vector3d> from, to, affine;
    Eigen::Matrix3d A;
    A << 1.1, 0.1, 0, -0.05, 0.9, 0.2, 0.0, 0.1, 1.2;
    const Vector3d b(0.3, -0.1, 0.7);
    for (int i = 0; i < 12; ++i) {
        from.emplace_back(u(rng), u(rng) + 1, u(rng));
        to.push_back(from.back() + 0.05 * Vector3d(u(rng), u(rng), u(rng)));
        affine.push_back(A * from.back() + b);
    }
    for (auto kernel : {registration::RbfKernel::ThinPlate, registration::RbfKernel::Multiquadric, registration::RbfKernel::Gaussian}) {
        const registration::RbfWarp warp(from, to, kernel, 0.2);
        for (std::size_t i = 0; i < from.size(); ++i) CHECK((warp(from[i]) - to[i]).norm() < 1e-9);
        const registration::RbfWarp linear(from, affine, kernel, 0.2);
        const Vector3d x(0.1, 0.8, -0.2);
        CHECK((linear(x) - (A * x + b)).norm() < 1e-8);
    }
    std::vector<Vector3d> flat = from;
    for (auto& p : flat) p.z() = 0;
    CHECK_THROWS_AS(registration::RbfWarp(flat, to, registration::RbfKernel::ThinPlate, 0.2), Error);
}
