// The fitter: analytic Jacobians against finite differences, the fitter's kinematics against the
// runtime's synthesis, accuracy on simulated measurements of the default model, and bad input.
#include "capi/handles.hpp"
#include "common/error.hpp"
#include "fitting/arrow_system.hpp"
#include "fitting/depth_image.hpp"
#include "fitting/fitter.hpp"
#include "anatomy/hand_closure.hpp"
#include "anatomy/joint_limits.hpp"
#include "anatomy/joint_roles.hpp"
#include "anatomy/named_poses.hpp"
#include "fitting/fit_problem.hpp"
#include "fitting/grid_index.hpp"
#include "fitting/head_search.hpp"
#include "fitting/wrist_search.hpp"
#include "fitting/nearest.hpp"
#include "fitting/normal_equations.hpp"
#include "fitting/robust.hpp"
#include "fitting/scan_normals.hpp"
#include "simulation/depth_camera.hpp"
#include "simulation/pose_library.hpp"
#include "simulation/simulate.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstring>
#include <memory>

using namespace ssc;

namespace {

struct DefaultModel {
    ssc_model* handle = nullptr;
    DefaultModel() { REQUIRE(ssc_model_load_default(nullptr, &handle) == SSC_OK); }
    ~DefaultModel() { ssc_model_release(handle); }
    const Model& model() const { return handle->model; }
};

const DefaultModel& default_model() {
    static DefaultModel m;  // loaded once for the whole file (read-only)
    return m;
}

// Joint j's rotation in a pose of unit quaternions (x, y, z, w per joint), and setting it.
Eigen::Quaterniond joint_rotation(const std::vector<float>& pose, std::size_t j) {
    const float* q = &pose[4 * j];
    return Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized();
}

void set_joint_rotation(std::vector<float>& pose, std::size_t j, const Eigen::Quaterniond& q) {
    float* out = &pose[4 * j];
    out[0] = float(q.x()), out[1] = float(q.y()), out[2] = float(q.z()), out[3] = float(q.w());
}

// Per vertex, whether it is in the model's vertex set `name`.
std::vector<uint8_t> vertex_set_flags(const Model& m, const std::string& name) {
    std::vector<uint8_t> flags(m.vertex_count(), 0);
    for (const auto& set : m.data().vertex_sets)
        if (set.name == name)
            for (uint32_t v : set.vertices) flags[v] = 1;
    return flags;
}

// Frame 0's state (and the problem's shape) set to the body a scan was made of.
void set_to_truth(fitting::FitProblem& problem, const Model& m, const std::vector<float>& shape, const std::vector<float>& pose) {
    fitting::FitState& state = problem.states()[0];
    state.shape.assign(shape.begin(), shape.end());
    state.shape.resize(problem.shape().size(), 0.0);
    problem.shape() = state.shape;
    for (uint32_t j = 0; j < m.joint_count(); ++j) state.pose[j] = joint_rotation(pose, j);
}

// The mean distance of the flagged vertices of a state's body from the truth's, metres.
double flagged_error(const Model& m, const fitting::FitState& s, const std::vector<uint8_t>& flags, const simulation::TrueBody& truth) {
    const auto fitted = simulation::fitted_vertices(m, s);
    double sum = 0;
    std::size_t n = 0;
    for (uint32_t v = 0; v < m.vertex_count(); ++v)
        if (flags[v]) sum += (fitted[v] - truth.vertices[v]).norm(), ++n;
    return sum / double(n);
}

fitting::FitState random_state(const fitting::Kinematics& kin, const Model& m, std::mt19937& rng) {
    fitting::FitState s = kin.zero_state();
    const auto shape = simulation::random_shape(m, rng);  // the whole body's; segment coefficients stay 0
    for (uint32_t k = 0; k < kin.components() && k < shape.size(); ++k) s.shape[k] = shape[k];
    const auto pose = simulation::random_pose(m, rng);
    for (uint32_t j = 0; j < m.joint_count(); ++j) s.pose[j] = Eigen::Quaterniond(pose[4 * j + 3], pose[4 * j], pose[4 * j + 1], pose[4 * j + 2]);
    s.pose[0] = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1, 0.1).normalized()));
    s.translation = Eigen::Vector3d(0.1, -0.2, 0.3);
    s.scale = 1.1;
    return s;
}

}  // namespace

TEST_CASE("the grid index finds the same nearest point within a radius as a brute-force search", "[fitting]") {
    std::mt19937 rng(7);
    std::normal_distribution<double> n(0, 1);
    std::uniform_real_distribution<double> u(0, 1);
    fitting::GridIndex grid(0.04);
    for (int set = 0; set < 8; ++set) {
        // Clustered points like a limb, plus a stray far point (which must not blow the grid up).
        std::vector<Eigen::Vector3d> points(set % 4 == 3 ? 1 : 300);
        for (auto& p : points) p = Eigen::Vector3d(0.05 * n(rng), 0.3 * u(rng), 0.05 * n(rng));
        if (set % 4 == 2) points.push_back(Eigen::Vector3d(40, -3, 7));
        grid.build(points);
        // The second four with the empty space indexed: few shells (queries reach past them), then
        // more than the farthest query reaches (as the start search's grid).
        ThreadPool pool(set % 2 ? 3 : 1);
        if (set >= 4) grid.index_empty_space(set >= 6 ? 8 : 2, pool);
        for (int q = 0; q < 2000; ++q) {
            const Eigen::Vector3d x(0.3 * n(rng), 0.4 * n(rng), 0.3 * n(rng));
            const double radius = 0.01 + 0.2 * u(rng);
            uint32_t want = fitting::GridIndex::kNone;
            double best = radius * radius;
            for (uint32_t i = 0; i < points.size(); ++i)
                if ((points[i] - x).squaredNorm() < best) best = (points[i] - x).squaredNorm(), want = i;
            double d2 = -1;
            const uint32_t got = grid.nearest(x, radius, &d2);
            REQUIRE(got == want);
            if (got != fitting::GridIndex::kNone) CHECK(d2 == best);
        }
    }
    const std::vector<Eigen::Vector3d> none;
    grid.build(none);
    CHECK(grid.nearest(Eigen::Vector3d::Zero(), 1.0, nullptr) == fitting::GridIndex::kNone);
    // An extent that overflows a double: still exact, point by point.
    const std::vector<Eigen::Vector3d> extreme = {Eigen::Vector3d(-1e308, 0, 0), Eigen::Vector3d(1e308, 0, 0), Eigen::Vector3d(0.5, 0, 0)};
    grid.build(extreme);
    double d2 = 0;
    CHECK(grid.nearest(Eigen::Vector3d(0.4, 0, 0), 1.0, &d2) == 2);
    CHECK(d2 == Approx(0.01));
    CHECK(grid.nearest(Eigen::Vector3d(-1e308, 1, 0), 2.0, nullptr) == 0);
}

TEST_CASE("normal equations from stacked blocks equal the sum of every block's J^T J", "[fitting][isa]") {
    // 75 parameters: the full column set (every fifth block) is wide enough for every tile of the
    // AVX2 product (16, 4 and single rows); the test also runs with SSCAPE_ISA=baseline (Eigen's).
    const uint32_t P = 75;
    Eigen::MatrixXd result[2];
    for (int run = 0; run < 2; ++run) {
        std::mt19937 data(5);  // the same blocks in both runs
        fitting::NormalEquations ne;
        Eigen::MatrixXd want = Eigen::MatrixXd::Zero(P, P);
        struct Block {
            uint32_t set;
            std::size_t row;
            Eigen::MatrixXd J;  // 3 x columns(set)
        };
        std::vector<Block> blocks;
        for (int b = 0; b < 60; ++b) {
            std::vector<uint32_t> cols;  // sorted, a few shared prefixes as the fitter's shape columns
            for (uint32_t c = 0; c < P; ++c)
                if (c < 5 || b % 5 == 0 || data() % 3 == 0) cols.push_back(c);
            Block blk{ne.column_set(cols), 0, Eigen::MatrixXd(3, cols.size())};
            blk.row = ne.reserve(blk.set, 3);
            for (Eigen::Index i = 0; i < blk.J.size(); ++i) blk.J.data()[i] = double(data() % 2001) / 1000.0 - 1.0;
            for (std::size_t a = 0; a < cols.size(); ++a)
                for (std::size_t c = 0; c < cols.size(); ++c) want(cols[a], cols[c]) += blk.J.col(Eigen::Index(a)).dot(blk.J.col(Eigen::Index(c)));
            blocks.push_back(std::move(blk));
        }
        ne.allocate();
        for (const Block& blk : blocks) {
            const std::size_t n = ne.columns(blk.set).size();
            double* rows = ne.rows(blk.set, blk.row);
            for (int r = 0; r < 3; ++r)
                for (std::size_t c = 0; c < n; ++c) rows[std::size_t(r) * n + c] = blk.J(r, Eigen::Index(c));
        }
        Eigen::MatrixXd H = Eigen::MatrixXd::Constant(P, P, 0.3);  // the lower triangle is left alone
        const Eigen::MatrixXd before = H;
        ThreadPool pool(run == 0 ? 1 : 3);
        ne.add_to_upper(H, pool);
        const Eigen::MatrixXd added = H - before;
        CHECK((Eigen::MatrixXd(added.triangularView<Eigen::Upper>()) - Eigen::MatrixXd(want.triangularView<Eigen::Upper>())).norm() < 1e-9 * want.norm());
        CHECK(H.triangularView<Eigen::StrictlyLower>().toDenseMatrix() == before.triangularView<Eigen::StrictlyLower>().toDenseMatrix());
        result[run] = H;
    }
    CHECK(result[0] == result[1]);  // the same sums for any thread count
}

TEST_CASE("an arrow system sums and solves as the dense normal equations of frames sharing a shape", "[fitting]") {
    // 6 shape columns, 4 frames of 9 columns: blocks touch the shape and one frame each.
    const uint32_t K = 6, B = 9, F = 4, P = K + F * B;
    std::mt19937 data(8);
    fitting::NormalEquations ne;
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(P, P);
    struct Block {
        uint32_t set;
        std::size_t row;
        Eigen::MatrixXd J;
    };
    std::vector<Block> blocks;
    for (int b = 0; b < 80; ++b) {
        const uint32_t f = uint32_t(b) % F;
        std::vector<uint32_t> cols;
        for (uint32_t c = 0; c < K; ++c)
            if (data() % 4) cols.push_back(c);
        for (uint32_t c = 0; c < B; ++c)
            if (c < 2 || data() % 2) cols.push_back(K + f * B + c);
        Block blk{ne.column_set(cols), 0, Eigen::MatrixXd(3, cols.size())};
        blk.row = ne.reserve(blk.set, 3);
        for (Eigen::Index i = 0; i < blk.J.size(); ++i) blk.J.data()[i] = double(data() % 2001) / 1000.0 - 1.0;
        for (std::size_t a = 0; a < cols.size(); ++a)
            for (std::size_t c = 0; c < cols.size(); ++c) dense(cols[a], cols[c]) += blk.J.col(Eigen::Index(a)).dot(blk.J.col(Eigen::Index(c)));
        blocks.push_back(std::move(blk));
    }
    for (uint32_t c = 0; c < P; ++c) dense(c, c) += 0.5;  // as the priors: definite
    ne.allocate();
    for (const Block& blk : blocks) {
        const std::size_t n = ne.columns(blk.set).size();
        double* rows = ne.rows(blk.set, blk.row);
        for (int r = 0; r < 3; ++r)
            for (std::size_t c = 0; c < n; ++c) rows[std::size_t(r) * n + c] = blk.J(r, Eigen::Index(c));
    }
    Eigen::VectorXd g(P);
    for (uint32_t c = 0; c < P; ++c) g[c] = double(data() % 2001) / 1000.0 - 1.0;
    Eigen::VectorXd solved[2];
    for (int run = 0; run < 2; ++run) {
        ThreadPool pool(run == 0 ? 1 : 3);
        fitting::ArrowSystem H;
        H.reset(K, B, F);
        for (uint32_t c = 0; c < P; ++c) H.add(c, c, 0.5);
        ne.add_to_upper(H, pool);
        for (uint32_t r = 0; r < P; ++r)
            for (uint32_t c = r; c < P; ++c) REQUIRE(H.at(r, c) == Approx(dense(r, c)).margin(1e-9));
        // The damped step on a subset of the columns (one frame left out entirely, as frames with
        // nothing active), against a dense solve of the same damped system.
        std::vector<int> cols;
        for (uint32_t c = 0; c < P; ++c)
            if (c % 5 != 3 && (c < K || (c - K) / B != 2)) cols.push_back(int(c));
        const double mu = 0.01;
        Eigen::MatrixXd A = dense(cols, cols);
        for (Eigen::Index i = 0; i < A.rows(); ++i) A(i, i) += mu * A(i, i) + 1e-12;
        const Eigen::VectorXd want = A.ldlt().solve(-g(cols));
        const Eigen::VectorXd d = H.damped_solve(g, cols, mu, pool);
        REQUIRE(d.size() == P);
        for (std::size_t i = 0; i < cols.size(); ++i) CHECK(d[cols[i]] == Approx(want[Eigen::Index(i)]).margin(1e-9));
        double untouched = 0;
        for (uint32_t c = 0; c < P; ++c)
            if (std::find(cols.begin(), cols.end(), int(c)) == cols.end()) untouched += std::abs(d[c]);
        CHECK(untouched == 0);
        solved[run] = d;
    }
    CHECK(solved[0] == solved[1]);  // the same for any thread count
}

TEST_CASE("trimming keeps the nearest pairs in their order and cuts ties first come first", "[fitting]") {
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> d(0, 40);  // few distinct distances: many ties at the cut
    std::vector<double> scratch;
    for (std::size_t n : {0, 1, 49, 50, 51, 777, 3000}) {
        std::vector<std::pair<double, int>> found(n);
        for (std::size_t i = 0; i < n; ++i) found[i] = {double(d(rng)), int(i)};
        std::vector<int> kept;
        fitting::append_trimmed(found, scratch, kept);
        // Reference: a stable sort by distance keeps the same set; the output is in input order.
        auto sorted = found;
        std::stable_sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        std::vector<int> want;
        for (std::size_t i = 0; i < fitting::kept_after_trimming(n); ++i) want.push_back(sorted[i].second);
        std::sort(want.begin(), want.end());
        REQUIRE(kept.size() == n - n / 50);
        CHECK(kept == want);
    }
}

TEST_CASE("fitter Jacobians match finite differences", "[fitting]") {
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, 12);
    fitting::Kinematics kin(lin);
    std::mt19937 rng(3);
    const fitting::FitState s = random_state(kin, m, rng);
    kin.update(s);
    const uint32_t P = kin.parameter_count();
    // A vertex on the left hand (long chain), one on the head, and a barycentric landmark.
    std::vector<fitting::SurfacePoint> points(3);
    points[0].vertex[0] = m.data().vertex_sets[3].vertices[10];  // hands
    points[1].vertex[0] = m.data().vertex_sets[0].vertices[5];   // head
    points[2].vertex[0] = 100, points[2].vertex[1] = 101, points[2].vertex[2] = 102;
    points[2].weight[0] = 0.2, points[2].weight[1] = 0.5, points[2].weight[2] = 0.3;
    for (const auto& p : points) {
        std::vector<double> J(3 * std::size_t(P), 0.0);
        kin.point_jacobian(p, J.data());
        const double h = 1e-6;
        double worst = 0, largest = 0;
        for (uint32_t i = 0; i < P; ++i) {
            std::vector<double> d(P, 0.0);
            fitting::FitState a = s, b = s;
            d[i] = h;
            kin.apply(d.data(), a);
            d[i] = -h;
            kin.apply(d.data(), b);
            fitting::Kinematics ka(lin), kb(lin);
            ka.update(a);
            kb.update(b);
            const Eigen::Vector3d num = (ka.point(p) - kb.point(p)) / (2 * h);
            for (int r = 0; r < 3; ++r) {
                worst = std::max(worst, std::abs(num[r] - J[std::size_t(r) * P + i]));
                largest = std::max(largest, std::abs(num[r]));
            }
        }
        INFO("worst difference " << worst << " of largest entry " << largest);
        CHECK(largest > 0.1);
        CHECK(worst < 1e-5 * largest);
    }
}

TEST_CASE("fitter kinematics reproduce the runtime's synthesis", "[fitting]") {
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    fitting::Kinematics kin(lin);
    std::mt19937 rng(5);
    const fitting::FitState s = random_state(kin, m, rng);
    kin.update(s);
    const auto body = simulation::fitted_vertices(m, s);
    double worst = 0;
    for (uint32_t v = 0; v < m.vertex_count(); v += 13) {
        fitting::SurfacePoint p;
        p.vertex[0] = v;
        worst = std::max(worst, (kin.point(p) - body[v]).norm());
    }
    CHECK(worst < 1e-5);  // float synthesis vs double kinematics
}

TEST_CASE("fitter kinematics with the segment shape spaces reproduce the runtime's synthesis, and their Jacobians", "[fitting][segments]") {
    const Model& m = default_model().model();
    REQUIRE(!m.segments().empty());
    const fitting::LinearModel lin(m, m.component_count(), nullptr, true);
    const uint32_t K = m.component_count(), S = uint32_t(m.segment_coefficient_count());
    CHECK(lin.whole_body == K);
    CHECK(lin.K == K + S);
    fitting::Kinematics kin(lin);
    std::mt19937 rng(7);
    fitting::FitState s = random_state(kin, m, rng);
    std::normal_distribution<double> sd(0.0, 1.0);
    for (uint32_t k = K; k < K + S; ++k) s.shape[k] = 1.5 * sd(rng);
    kin.update(s);
    const auto body = simulation::fitted_vertices(m, s);  // the float synthesis, segments set
    fitting::FitState without = s;
    without.shape.resize(K);
    const auto whole_only = simulation::fitted_vertices(m, without);
    double worst = 0, moved = 0;
    for (uint32_t v = 0; v < m.vertex_count(); v += 7) {
        fitting::SurfacePoint p;
        p.vertex[0] = v;
        worst = std::max(worst, (kin.point(p) - body[v]).norm());
        moved = std::max(moved, (body[v] - whole_only[v]).norm());
    }
    CHECK(moved > 0.01);    // the segments change the body
    CHECK(worst < 2e-5);   // and the kinematics follow them (16-bit segment bases)

    // The segment columns of a hand vertex's Jacobian against finite differences.
    fitting::SurfacePoint p;
    p.vertex[0] = m.data().vertex_sets[3].vertices[10];
    const uint32_t P = kin.parameter_count();
    std::vector<double> J(3 * std::size_t(P), 0.0);
    kin.point_jacobian(p, J.data());
    double largest = 0, diff = 0;
    for (uint32_t i = K; i < K + S; ++i) {
        std::vector<double> d(P, 0.0);
        fitting::FitState a = s, b = s;
        d[i] = 1e-6;
        kin.apply(d.data(), a);
        d[i] = -1e-6;
        kin.apply(d.data(), b);
        fitting::Kinematics ka(lin), kb(lin);
        ka.update(a);
        kb.update(b);
        const Eigen::Vector3d num = (ka.point(p) - kb.point(p)) / 2e-6;
        for (int r = 0; r < 3; ++r) diff = std::max(diff, std::abs(num[r] - J[std::size_t(r) * P + i])), largest = std::max(largest, std::abs(num[r]));
    }
    INFO("worst difference " << diff << " of largest entry " << largest);
    CHECK(largest > 0.001);
    CHECK(diff < 1e-5 * largest);

    // Only after all of the whole body's components.
    CHECK_THROWS_AS(fitting::LinearModel(m, 10, nullptr, true), Error);
}

TEST_CASE("landmark fits recover held-out bodies in any heading", "[fitting]") {
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    std::mt19937 rng(11);
    double total = 0;
    const int trials = 3;
    for (int t = 0; t < trials; ++t) {
        auto truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng), Eigen::Vector3d(0.5, 0, 0));
        simulation::transform_body(truth, Eigen::AngleAxisd(2.0 * t + 0.5, Eigen::Vector3d::UnitY()).toRotationMatrix(), Eigen::Vector3d(0, 0, 2));
        fitting::Frame frame;
        frame.landmarks = simulation::simulate_landmarks(m, truth, 0.01, true, rng);
        REQUIRE(frame.landmarks.size() == 67);
        const auto sol = fitting::fit(lin, {frame}, fitting::FitOptions{});
        const double err = simulation::mean_vertex_error(simulation::fitted_vertices(m, sol.frames[0]), truth.vertices);
        INFO("trial " << t << ": mean vertex error " << err * 1e3 << " mm, landmark rms " << sol.report.landmark_rms * 1e3 << " mm");
        CHECK(err < 0.025);
        CHECK(sol.report.landmark_rms < 0.02);
        total += err;
    }
    CHECK(total / trials < 0.018);
}

namespace {

// Turns and moves a true body, scans it (`points` points, the simulator's noise, holes and
// outliers) and fits the scan with the default options; returns the solution and its mean vertex error.
std::pair<fitting::FitSolution, double> fit_scan(const Model& m, const fitting::LinearModel& lin, simulation::TrueBody truth,
                                                 double heading, const Eigen::Vector3d& shift, std::mt19937& rng,
                                                 uint32_t points = 8000) {
    simulation::transform_body(truth, Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitY()).toRotationMatrix(), shift);
    fitting::Frame frame;
    simulation::CloudSpec spec;
    spec.points = points;
    frame.clouds.push_back(simulation::simulate_cloud(m, truth, spec, rng));
    auto sol = fitting::fit(lin, {frame}, fitting::FitOptions{});
    const double err = simulation::mean_vertex_error(simulation::fitted_vertices(m, sol.frames[0]), truth.vertices);
    return {std::move(sol), err};
}

}  // namespace

TEST_CASE("scan fits of a mildly posed body are accurate", "[fitting]") {
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    std::mt19937 rng(21);
    auto truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng, 0.4), Eigen::Vector3d::Zero());
    const auto [sol, err] = fit_scan(m, lin, truth, 2.5, Eigen::Vector3d(0.2, 0.1, 1.5), rng);
    INFO("mean vertex error " << err * 1e3 << " mm, point mean " << sol.report.point_mean * 1e3 << " mm");
    CHECK(err < 0.012);
    CHECK(sol.report.inlier_fraction > 0.6);
}

TEST_CASE("scan fits find fists and half-closed hands, and leave open hands open", "[fitting][hands]") {
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    std::vector<uint8_t> in_hand(m.vertex_count(), 0);
    for (const auto& set : m.data().vertex_sets)
        if (set.name == "hands")
            for (uint32_t v : set.vertices) in_hand[v] = 1;
    std::mt19937 rng(41);
    // Left hand a fist, right hand half closed; then both open.
    for (const auto& closure : {std::array<double, 2>{1.0, 0.5}, std::array<double, 2>{0.0, 0.0}}) {
        std::vector<float> pose = simulation::random_pose(m, rng, 0.4);
        for (int hand = 0; hand < 2; ++hand)
            for (const auto& jr : anatomy::hand_closure(m, hand == 0 ? 'l' : 'r', closure[hand])) {
                float* q = &pose[4 * std::size_t(jr.joint)];
                q[0] = float(jr.rotation.x()), q[1] = float(jr.rotation.y()), q[2] = float(jr.rotation.z()), q[3] = float(jr.rotation.w());
            }
        const auto truth = simulation::make_body(m, simulation::random_shape(m, rng), pose, Eigen::Vector3d::Zero());
        const auto [sol, err] = fit_scan(m, lin, truth, 0.5, Eigen::Vector3d(0, 0.1, 1.5), rng, 20000);
        const auto fitted = simulation::fitted_vertices(m, sol.frames[0]);
        auto moved = truth;  // where fit_scan put the scanned body
        simulation::transform_body(moved, Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()).toRotationMatrix(), Eigen::Vector3d(0, 0.1, 1.5));
        double hands = 0;
        std::size_t n = 0;
        for (uint32_t v = 0; v < m.vertex_count(); ++v)
            if (in_hand[v]) hands += (fitted[v] - moved.vertices[v]).norm(), ++n;
        hands /= double(n);
        INFO("true closures " << closure[0] << " " << closure[1] << ", found " << sol.frames[0].hand_closure[0] << " "
                              << sol.frames[0].hand_closure[1] << "; hands " << hands * 1e3 << " mm, all " << err * 1e3 << " mm");
        for (int hand = 0; hand < 2; ++hand) CHECK(std::abs(sol.frames[0].hand_closure[hand] - closure[hand]) <= 0.25);
        CHECK(hands < 0.008);  // the fingers of a fist fitted open are off by 2 to 3 cm
    }
}

TEST_CASE("the head search turns back a head the fit left turned away and keeps one that is right", "[fitting][head]") {
    // Fits of people bending sideways or reaching ended with the head turned 20 to 40 degrees from
    // the person's while it sat on the scan (head vertices 37 to 75 mm off, reported converged).
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    const std::vector<anatomy::JointLimit>& limits = lin.limits;
    const int64_t neck = m.find_joint("neck_01"), head = m.find_joint("head");
    REQUIRE(neck >= 0);
    REQUIRE(head >= 0);
    const std::vector<uint8_t> in_head = vertex_set_flags(m, "head");
    std::mt19937 rng(47);
    std::vector<float> pose = simulation::random_pose(m, rng, 0.3);
    // Turned and tipped within the joints' ranges: about 45 degrees of turn, 25 of tilt.
    set_joint_rotation(pose, std::size_t(neck), anatomy::rotation_from_angles(limits[std::size_t(neck)], Eigen::Vector3d(0.15, 0.45, 0.25)));
    set_joint_rotation(pose, std::size_t(head), anatomy::rotation_from_angles(limits[std::size_t(head)], Eigen::Vector3d(0.1, 0.35, 0.2)));
    const std::vector<float> shape = simulation::random_shape(m, rng);
    const auto truth = simulation::make_body(m, shape, pose, Eigen::Vector3d::Zero());
    fitting::Frame frame;
    simulation::CloudSpec spec;
    spec.points = 30000;
    frame.clouds.push_back(simulation::simulate_cloud(m, truth, spec, rng));
    fitting::FitProblem problem(lin, {frame}, fitting::FitOptions{}, nullptr);
    set_to_truth(problem, m, shape, pose);
    fitting::FitState& state = problem.states()[0];
    auto head_error = [&](const fitting::FitState& s) { return flagged_error(m, s, in_head, truth); };
    REQUIRE(head_error(state) < 1e-4);  // the state is the truth
    const fitting::FitState truth_state = state;
    problem.update_kinematics();
    const double truth_distance = problem.mean_scan_distance(0, 0.02);
    // A head that is right: the search may propose a small turn (a 2 % gain of the head's own
    // measure), which leaves the fit farther from the scan, so the solver's check
    // (keep_if_closer) takes it back.
    if (fitting::search_head(problem.kin(0), problem.body(), state, problem.cloud_view(0), problem.vertex_sample(), problem.pool())) {
        problem.update_kinematics();
        const double proposed_distance = problem.mean_scan_distance(0, 0.02);
        INFO("a right head turned by " << head_error(state) * 1e3 << " mm: scan to fit " << proposed_distance * 1e3 << " mm against "
                                       << truth_distance * 1e3 << " mm");
        CHECK(proposed_distance > truth_distance);
        state = truth_state;
    }
    CHECK(head_error(state) < 1e-4);
    // Looking straight ahead instead: turned back.
    state.pose[std::size_t(neck)] = state.pose[std::size_t(head)] = Eigen::Quaterniond::Identity();
    problem.update_kinematics();
    const double before = head_error(state);
    problem.update_kinematics();
    const double ahead_distance = problem.mean_scan_distance(0, 0.02);
    CHECK(fitting::search_head(problem.kin(0), problem.body(), state, problem.cloud_view(0), problem.vertex_sample(), problem.pool()));
    const double after = head_error(state);
    INFO("head vertices " << before * 1e3 << " mm off looking ahead, " << after * 1e3 << " mm after the search");
    CHECK(before > 0.03);
    CHECK(after < 0.01);  // the fine stage that follows a turn settles the rest (6.6 mm here)
    // The turned-back head lies closer to the scan than the one looking ahead: the solver keeps it.
    problem.update_kinematics();
    const double turned_distance = problem.mean_scan_distance(0, 0.02);
    INFO("scan to fit: " << ahead_distance * 1e3 << " mm looking ahead, " << turned_distance * 1e3 << " mm turned back, "
                         << truth_distance * 1e3 << " mm the truth");
    CHECK(turned_distance < ahead_distance);
    CHECK(truth_distance <= turned_distance);
}

TEST_CASE("the wrist search turns back a forearm the fit left turned over", "[fitting][wrists]") {
    // Fits of hands behind the head, on the knees or at the throat ended with the forearm turned
    // over or the wrist bent the wrong way while the hand lay on its points (hands 30 to 150 mm off).
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    const std::vector<anatomy::JointLimit>& limits = lin.limits;
    const int64_t elbow = m.find_joint("lowerarm_l"), wrist = m.find_joint("hand_l");
    REQUIRE(elbow >= 0);
    REQUIRE(wrist >= 0);
    const std::size_t je = std::size_t(elbow), jw = std::size_t(wrist);
    const std::vector<uint8_t> in_hands = vertex_set_flags(m, "hands");
    std::mt19937 rng(61);
    std::vector<float> pose = simulation::random_pose(m, rng, 0.3);
    // The arm held out sideways, the forearm turned 60 degrees one way and the wrist bent 30.
    const int64_t shoulder = m.find_joint("upperarm_l");
    REQUIRE(shoulder >= 0);
    set_joint_rotation(pose, std::size_t(shoulder), anatomy::rotation_from_angles(limits[std::size_t(shoulder)], Eigen::Vector3d(-0.3, 0, -0.8)));
    const Eigen::Vector3d e = anatomy::anatomical_angles(limits[je], joint_rotation(pose, je));
    set_joint_rotation(pose, je, anatomy::rotation_from_angles(limits[je], Eigen::Vector3d(e[0], 60 * M_PI / 180, e[2])));
    set_joint_rotation(pose, jw, anatomy::rotation_from_angles(limits[jw], Eigen::Vector3d(30 * M_PI / 180, 0, 0)));
    const std::vector<float> shape = simulation::random_shape(m, rng);
    const auto truth = simulation::make_body(m, shape, pose, Eigen::Vector3d::Zero());
    fitting::Frame frame;
    simulation::CloudSpec spec;
    spec.points = 30000;
    spec.missing = 0;  // the hand scanned (20 round holes can swallow it)
    frame.clouds.push_back(simulation::simulate_cloud(m, truth, spec, rng));
    fitting::FitProblem problem(lin, {frame}, fitting::FitOptions{}, nullptr);
    set_to_truth(problem, m, shape, pose);
    fitting::FitState& state = problem.states()[0];
    auto hand_error = [&](const fitting::FitState& s) { return flagged_error(m, s, in_hands, truth); };
    REQUIRE(hand_error(state) < 1e-4);  // the state is the truth
    problem.update_kinematics();
    const double truth_distance = problem.mean_scan_distance(0, 0.02);
    // Turned over the other way, the wrist straight: the search turns it back, and the fit then
    // lies closer to the scan (the solver keeps it).
    state.pose[je] = anatomy::rotation_from_angles(limits[je], Eigen::Vector3d(e[0], -60 * M_PI / 180, e[2]));
    state.pose[jw] = Eigen::Quaterniond::Identity();
    problem.update_kinematics();
    const double before = hand_error(state), before_distance = problem.mean_scan_distance(0, 0.02);
    CHECK(fitting::search_wrists(problem.kin(0), problem.body(), state, problem.cloud_view(0), problem.vertex_sample(), problem.pool()));
    problem.update_kinematics();
    const double after = hand_error(state), after_distance = problem.mean_scan_distance(0, 0.02);
    INFO("hand vertices " << before * 1e3 << " mm off turned over, " << after * 1e3 << " mm after the search; scan to fit " << before_distance * 1e3
                          << " -> " << after_distance * 1e3 << " mm (the truth " << truth_distance * 1e3 << ")");
    CHECK(before > 0.02);
    CHECK(after < 0.25 * before);
    CHECK(after_distance < before_distance);
}

TEST_CASE("an arm turned over about its own line swings its elbow round and leaves the scan a little way off", "[fitting][wrists]") {
    // Fits of arms raised or reaching down ended with a straight arm turned over, palm and elbow
    // facing the wrong way, judged right (the arm lies on its points): the solver tries each arm
    // turned half a turn about its line (turn_arm_over) when a fit leaves its scan a little way off.
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    const std::vector<anatomy::JointLimit>& limits = lin.limits;
    const int64_t shoulder = m.find_joint("upperarm_l"), elbow = m.find_joint("lowerarm_l"), wrist = m.find_joint("hand_l");
    REQUIRE(shoulder >= 0);
    REQUIRE(elbow >= 0);
    REQUIRE(wrist >= 0);
    std::mt19937 rng(67);
    std::vector<float> pose = simulation::random_pose(m, rng, 0.3);
    // The arm held out sideways, the elbow bent 60 degrees.
    set_joint_rotation(pose, std::size_t(shoulder), anatomy::rotation_from_angles(limits[std::size_t(shoulder)], Eigen::Vector3d(-0.3, 0, -0.8)));
    const Eigen::Vector3d e = anatomy::anatomical_angles(limits[std::size_t(elbow)], joint_rotation(pose, std::size_t(elbow)));
    set_joint_rotation(pose, std::size_t(elbow), anatomy::rotation_from_angles(limits[std::size_t(elbow)], Eigen::Vector3d(-60 * M_PI / 180, e[1], e[2])));
    const std::vector<float> shape = simulation::random_shape(m, rng);
    const auto truth = simulation::make_body(m, shape, pose, Eigen::Vector3d::Zero());
    fitting::Frame frame;
    simulation::CloudSpec spec;
    spec.points = 30000;
    spec.missing = 0;
    frame.clouds.push_back(simulation::simulate_cloud(m, truth, spec, rng));
    fitting::FitProblem problem(lin, {frame}, fitting::FitOptions{}, nullptr);
    set_to_truth(problem, m, shape, pose);
    fitting::FitState& state = problem.states()[0];
    fitting::Kinematics& kin = problem.kin(0);
    const std::vector<uint8_t> in_hands = vertex_set_flags(m, "hands");
    REQUIRE(flagged_error(m, state, in_hands, truth) < 1e-4);  // the state is the truth
    kin.update(state, false);
    const Eigen::Vector3d s0 = kin.joint_position(uint32_t(shoulder)), e0 = kin.joint_position(uint32_t(elbow)),
                          w0 = kin.joint_position(uint32_t(wrist));
    problem.update_kinematics();
    const double truth_off = problem.share_beyond_plane(0, 0.008, 0.05);

    REQUIRE(fitting::turn_arm_over(kin, state, anatomy::Side::Left));
    // The wrist and shoulder stay; the elbow is mirrored through the shoulder-wrist line.
    const Eigen::Vector3d axis = (w0 - s0).normalized(), foot = s0 + axis * axis.dot(e0 - s0);
    CHECK((kin.joint_position(uint32_t(shoulder)) - s0).norm() < 1e-9);
    CHECK((kin.joint_position(uint32_t(wrist)) - w0).norm() < 1e-9);
    CHECK((kin.joint_position(uint32_t(elbow)) - (2 * foot - e0)).norm() < 1e-9);
    CHECK((e0 - foot).norm() > 0.02);  // a bent elbow: it really moved
    problem.update_kinematics();
    const double turned_off = problem.share_beyond_plane(0, 0.008, 0.05);
    const double hand_off = flagged_error(m, state, in_hands, truth);
    INFO("scan beyond 8 mm: " << 100 * truth_off << " % the truth, " << 100 * turned_off << " % the arm turned over (hand vertices " << hand_off * 1e3
                              << " mm off)");
    CHECK(hand_off > 0.03);
    CHECK(turned_off > 4 * truth_off + 0.01);
    // Turned again: the arm as it was.
    REQUIRE(fitting::turn_arm_over(kin, state, anatomy::Side::Left));
    CHECK(flagged_error(m, state, in_hands, truth) < 1e-6);
}

TEST_CASE("the fitter's segment shape spaces fit proportions the whole body's cannot hold", "[fitting][segments]") {
    // A body whose head, arms, torso and legs are each shaped beyond what the whole-body
    // components make of them (each segment's first component at 1.5 to 2 SD): fitted with the
    // segments (FitOptions::segments, the default) it comes far closer than with the whole body's
    // components alone, which cannot represent it.
    const Model& m = default_model().model();
    REQUIRE(m.segments().size() == 6);
    std::mt19937 rng(71);
    Body body(m, nullptr);
    const std::vector<float> shape = simulation::random_shape(m, rng);
    body.set_shape(shape.data(), uint32_t(shape.size()));
    std::uniform_real_distribution<float> sd(1.5f, 2.0f);
    for (uint32_t g = 0; g < m.segments().size(); ++g) {
        std::vector<float> c(m.segments()[g].components, 0.f);
        c[0] = (g % 2 ? -1.f : 1.f) * sd(rng);
        body.set_segment_shape(g, c.data(), uint32_t(c.size()));
    }
    const uint32_t V = m.vertex_count();
    const float* rest = body.rest_planar();
    std::vector<Eigen::Vector3d> rest_vertices(V);
    for (uint32_t v = 0; v < V; ++v) rest_vertices[v] = Eigen::Vector3d(rest[v], rest[V + v], rest[2 * std::size_t(V) + v]);
    const auto truth = simulation::pose_rest_vertices(m, rest_vertices, simulation::random_pose(m, rng, 0.3), Eigen::Vector3d(0.1, 0, 0.2));
    simulation::CloudSpec spec;
    spec.points = 30000;
    const fitting::PointCloud cloud = simulation::simulate_cloud(m, truth, spec, rng);
    auto fitted_error = [&](bool segments) {
        fitting::FitOptions o;
        o.components = m.component_count();
        o.segments = segments;
        fitting::Fitter fitter(m, o);
        fitter.add_cloud(0, cloud);
        const fitting::FitReport& report = fitter.solve();
        CHECK(report.converged);
        return simulation::mean_vertex_error(fitter.vertices(0), truth.vertices);
    };
    const double with = fitted_error(true), without = fitted_error(false);
    INFO("mean vertex error " << with * 1e3 << " mm with the segments, " << without * 1e3 << " mm without");
    CHECK(with < 0.6 * without);
    CHECK(with < 0.006);
}

TEST_CASE("booth scans with landmarks of people folded or crouching are fitted in the landmarks' pose", "[fitting][landmarks]") {
    // From the landmarks' rigid alignment alone the scan's correspondences started from the rest
    // pose: crouching, bending forward and the squats ended 50 to 370 mm off, reported failed,
    // with 73 landmarks placed to 5 mm (pose library, MakeHuman people: 84 % success).
    const Model& m = default_model().model();
    std::mt19937 rng(53);
    std::uniform_real_distribution<double> turn(-M_PI, M_PI);
    const auto& library = simulation::pose_library();
    for (const char* name : {"crouching", "bending_forward", "touching_toes", "squat_arms_raised"}) {
        if (test::sanitized && std::string(name) != "touching_toes") continue;  // one under the sanitizers
        const auto pose = std::find_if(library.begin(), library.end(), [&](const simulation::LibraryPose& p) { return p.name == name; });
        REQUIRE(pose != library.end());
        simulation::TrueBody b = simulation::make_body(m, simulation::random_shape(m, rng), simulation::library_pose(m, *pose), Eigen::Vector3d::Zero());
        simulation::transform_body(b, Eigen::AngleAxisd(turn(rng), Eigen::Vector3d::UnitY()).toRotationMatrix() * simulation::library_orientation(*pose),
                                   Eigen::Vector3d(0.3, 0, -0.2));
        simulation::BoothSpec spec;
        spec.points = 25000;
        fitting::FitOptions options;
        options.components = m.component_count();
        fitting::Fitter fitter(m, options);
        fitter.add_cloud(0, simulation::booth_scan(m, b, spec, rng));
        fitter.add_landmarks(0, simulation::simulate_landmarks(m, b, 0.005, true, rng));
        const fitting::FitReport& report = fitter.solve();
        const std::vector<Eigen::Vector3d> fitted = fitter.vertices(0);
        const double error = simulation::mean_vertex_error(fitted, b.vertices);
        INFO(name << ": " << error * 1000 << " mm; " << report.problem_text);
        CHECK(report.converged);
        CHECK(error < 0.01);
    }
}

TEST_CASE("clutter around a scanned body is not taken for a failed fit", "[fitting]") {
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    std::mt19937 rng(43);
    const auto truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng, 0.4), Eigen::Vector3d::Zero());
    simulation::CloudSpec spec;
    spec.points = 20000;
    spec.outliers = 0.08;  // uniform in the body's box: 8 % of the points
    fitting::Frame frame;
    frame.clouds.push_back(simulation::simulate_cloud(m, truth, spec, rng));
    const auto sol = fitting::fit(lin, {frame}, fitting::FitOptions{});
    const double err = simulation::mean_vertex_error(simulation::fitted_vertices(m, sol.frames[0]), truth.vertices);
    INFO("unexplained " << sol.report.unexplained << ", error " << err * 1e3 << " mm, restarts " << sol.report.restarts);
    CHECK(err < 0.006);
    CHECK(sol.report.unexplained < 0.01);
    CHECK(sol.report.converged);
    CHECK_FALSE(sol.report.implausible);
}

TEST_CASE("frames of one person fitted together share a shape and fit each frame as well as alone or better", "[fitting]") {
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    std::mt19937 rng(31);
    const auto shape = simulation::random_shape(m, rng);
    std::vector<fitting::Frame> frames(4);
    std::vector<simulation::TrueBody> truths;
    for (std::size_t f = 0; f < frames.size(); ++f) {
        auto truth = simulation::make_body(m, shape, simulation::random_pose(m, rng), Eigen::Vector3d::Zero());
        simulation::transform_body(truth, Eigen::AngleAxisd(0.8 * double(f), Eigen::Vector3d::UnitY()).toRotationMatrix(), Eigen::Vector3d(0, 0.1, 1.5));
        simulation::CloudSpec spec;
        spec.points = 8000;
        frames[f].clouds.push_back(simulation::simulate_cloud(m, truth, spec, rng));
        truths.push_back(std::move(truth));
    }
    const auto together = fitting::fit(lin, frames, fitting::FitOptions{});
    REQUIRE(together.frames.size() == frames.size());
    double sum_together = 0, sum_alone = 0;
    for (std::size_t f = 0; f < frames.size(); ++f) {
        CHECK(together.frames[f].shape == together.shape);  // one shape
        const double e = simulation::mean_vertex_error(simulation::fitted_vertices(m, together.frames[f]), truths[f].vertices);
        const auto alone = fitting::fit(lin, {frames[f]}, fitting::FitOptions{});
        const double a = simulation::mean_vertex_error(simulation::fitted_vertices(m, alone.frames[0]), truths[f].vertices);
        INFO("frame " << f << ": together " << e * 1e3 << " mm, alone " << a * 1e3 << " mm");
        CHECK(e < 0.012);
        sum_together += e, sum_alone += a;
    }
    CHECK(sum_together < 1.05 * sum_alone);
}

TEST_CASE("scans of people crouching or bent forward fit, or say that they failed", "[fitting]") {
    // Started from the rest pose only, every such fit of the benchmark's hard poses ended upside
    // down or standing (400-500 mm mean vertex error) and reported success. The start search now
    // also places the template crouching, seated and bent forward: this crouching scan fits. Bent
    // forward failed at some headings (this one: placed 10-20 degrees off by the first rigid
    // steps); the restarts from the start poses placed again with more steps (placed_again in
    // solver.cpp) fit it. Any fit that still fails must not report converged. (Other crouching
    // bodies can still end with the limbs folded the wrong way while explaining the scan's
    // surface, undetected: drawn first from this generator, a crouch ended 66 mm off with 2.5 % of
    // its scan unexplained, reported converged.)
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    std::mt19937 rng(24);
    for (const char* pose : {"bending_forward", "crouching"}) {
        const auto truth = simulation::make_body(m, simulation::random_shape(m, rng), anatomy::named_pose(m, pose), Eigen::Vector3d::Zero());
        const auto [sol, err] = fit_scan(m, lin, truth, 2.0, Eigen::Vector3d(0, 0.1, 1.5), rng);
        INFO(pose << ": mean vertex error " << err * 1e3 << " mm, unexplained " << sol.report.unexplained << ", converged "
                  << sol.report.converged);
        CHECK(err < 0.015);
        CHECK((err < 0.015 || !sol.report.converged));
    }
}

TEST_CASE("people bent forward are found at any heading by the start poses placed again", "[fitting]") {
    // The first rigid placement of the bent-forward template (3 steps from the principal axes)
    // stopped 10-20 degrees off, and the fits from there ended 100-250 mm off, reported failed;
    // the restarts from the start poses placed again with more steps (placed_again in solver.cpp)
    // find them (the benchmark's hard poses: 7 of 10 bent-forward fits failed before, 1 after).
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    std::mt19937 rng(31);
    for (const double heading : {0.5, 2.0, 3.5, 5.0}) {
        if (test::sanitized && heading != 0.5) continue;  // one under the sanitizers (92 s for all four), restarted as in Release
        const auto truth = simulation::make_body(m, simulation::random_shape(m, rng), anatomy::named_pose(m, "bending_forward"), Eigen::Vector3d::Zero());
        const auto [sol, err] = fit_scan(m, lin, truth, heading, Eigen::Vector3d(0, 0.1, 1.5), rng);
        INFO("heading " << heading << ": mean vertex error " << err * 1e3 << " mm, " << sol.report.restarts << " restarts, converged "
                        << sol.report.converged);
        CHECK(err < 0.015);
        CHECK(sol.report.converged);
    }
}

TEST_CASE("a scan with some normals missing keeps the given ones and estimates the rest, signed", "[fitting]") {
    // Real scans carry zero normals here and there; they used to make the reader drop every normal.
    const Model& m = default_model().model();
    std::mt19937 rng(22);
    const auto truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng, 0.4), Eigen::Vector3d::Zero());
    simulation::CloudSpec spec;
    spec.points = 20000;
    spec.outliers = 0;
    auto cloud = simulation::simulate_cloud(m, truth, spec, rng);
    const auto reference = cloud.normals;
    std::vector<Eigen::Vector3d> normals = reference;
    for (std::size_t i = 0; i < normals.size(); i += 3) normals[i].setZero();  // a third unknown
    const fitting::PointIndex index(cloud.points);
    CHECK(fitting::estimate_missing_normals(cloud.points, index, normals));
    std::size_t agree = 0, estimated = 0;
    for (std::size_t i = 0; i < normals.size(); ++i) {
        REQUIRE(std::abs(normals[i].norm() - 1) < 1e-9);
        if (i % 3 != 0) {
            CHECK(normals[i] == reference[i]);  // given normals are kept as they are
            continue;
        }
        ++estimated;
        agree += normals[i].dot(reference[i]) > 0.7;  // same sign, within 45 degrees
    }
    INFO(agree << " of " << estimated << " estimated normals agree with the surface's");
    CHECK(double(agree) / double(estimated) > 0.95);
    // With none given, nothing can sign them.
    std::vector<Eigen::Vector3d> none(cloud.points.size(), Eigen::Vector3d::Zero());
    CHECK_FALSE(fitting::estimate_missing_normals(cloud.points, index, none));
}

TEST_CASE("scan fits reach arms raised overhead and a seated pose from the rest-pose start", "[fitting]") {
    // Beyond what the coarse stage's correspondences reach from the A-pose: the limb search must find them.
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    std::mt19937 rng(23);
    for (const char* pose : {"arms_raised", "sitting"}) {
        const auto truth = simulation::make_body(m, simulation::random_shape(m, rng), anatomy::named_pose(m, pose), Eigen::Vector3d::Zero());
        const double err = fit_scan(m, lin, truth, 0.7, Eigen::Vector3d(0, 0.1, 1.5), rng).second;
        INFO(pose << ": mean vertex error " << err * 1e3 << " mm");
        CHECK(err < 0.015);
    }
}

namespace {

// A scan as the fit benchmark (tests/bench) makes one: a random body and pose in a random heading,
// 20,000 points (fit_scan). Draws from rng in the benchmark's order.
std::pair<fitting::FitSolution, double> fit_benchmark_scan(const Model& m, const fitting::LinearModel& lin, std::mt19937& rng) {
    auto truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng), Eigen::Vector3d::Zero());
    std::uniform_real_distribution<double> heading(-M_PI, M_PI);
    const double angle = heading(rng);
    return fit_scan(m, lin, truth, angle, Eigen::Vector3d(0.1, 0.2, 1.5), rng, 20000);
}

// The fit benchmark's scan trial whose draws start after `draws` of seed 200's (sscape_fit_bench
// --scenario scan), fitted with the default model.
std::pair<fitting::FitSolution, double> fit_benchmark_trial(unsigned long long draws) {
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    std::mt19937 rng(200);
    rng.discard(draws);
    return fit_benchmark_scan(m, lin, rng);
}

}  // namespace

TEST_CASE("a fit that cannot explain its scan is reported as failed, through the C API", "[fitting][capi]") {
    // Two people a metre apart in one scan: the body fits one of them and leaves half the scan
    // unexplained; it must not report success.
    const Model& m = default_model().model();
    std::mt19937 rng(41);
    std::vector<float> points, normals;
    for (int person = 0; person < 2; ++person) {
        auto truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng, 0.3), Eigen::Vector3d::Zero());
        simulation::transform_body(truth, Eigen::Matrix3d::Identity(), Eigen::Vector3d(person ? 1.0 : 0.0, 0, 2.0));
        simulation::CloudSpec spec;
        spec.points = 6000;
        const auto cloud = simulation::simulate_cloud(m, truth, spec, rng);
        for (std::size_t i = 0; i < cloud.points.size(); ++i)
            for (int a = 0; a < 3; ++a) points.push_back(float(cloud.points[i][a])), normals.push_back(float(cloud.normals[i][a]));
    }
    ssc_fitter* fitter = nullptr;
    REQUIRE(ssc_fitter_create(default_model().handle, nullptr, &fitter) == SSC_OK);
    REQUIRE(ssc_fitter_add_points(fitter, 0, points.data(), normals.data(), nullptr, uint32_t(points.size() / 3), 0) == SSC_OK);
    ssc_fit_report report{};
    report.struct_size = sizeof report;
    REQUIRE(ssc_fitter_solve(fitter, nullptr, nullptr, &report) == SSC_OK);
    ssc_fitter_destroy(fitter);
    INFO("unexplained " << report.unexplained_fraction << ", restarts " << report.restarts);
    CHECK(report.unexplained_fraction > SSC_FIT_UNEXPLAINED_LIMIT);
    CHECK(report.converged == 0);
}

TEST_CASE("a scan fit that ends implausible is redone from the next start candidate", "[fitting]") {
    // The benchmark's scan trial 109 (its generator advanced past trials 0-108): the start search's
    // short fits prefer the body turned round, whose full fit then ends with joints far past their
    // limits (545 mm mean vertex error before restarts). Should a change to the simulator or the
    // start search make this fit succeed at once, restarts is 0: pick another such trial
    // (SSCAPE_BENCH_VERBOSE=1 sscape_fit_bench --trials 140 --scenario scan lists restarts).
    const auto [sol, err] = fit_benchmark_trial(34112100);
    INFO("mean vertex error " << err * 1e3 << " mm, " << sol.report.restarts << " restarts");
    CHECK(sol.report.restarts >= 1);
    CHECK(err < 0.01);
}

TEST_CASE("a scan fit that leaves its scan loosely explained is redone from the next start candidate", "[fitting]") {
    // The benchmark's scan trial 23 (its generator advanced past trials 0-22): the first fit is
    // judged right (no joint past its range, nothing unexplained) but leaves 2.2 % of the scan
    // over 2.5 cm from its surface, its trunk upright where the person leans forward; it ended
    // 4.34 mm off before loose fits were redone. Should a change make this fit right at once,
    // restarts is 0: pick another trial (SSCAPE_BENCH_VERBOSE=1 sscape_fit_bench --trials 30
    // --scenario scan lists restarts).
    const auto [sol, err] = fit_benchmark_trial(7194160);
    INFO("mean vertex error " << err * 1e3 << " mm, " << sol.report.restarts << " restarts");
    CHECK(sol.report.restarts >= 1);
    CHECK(err < 0.002);
    CHECK(sol.report.converged);
}

TEST_CASE("the start search goes on to the last rigid candidates while the checked ones end implausible", "[fitting]") {
    // A scan whose right heading the rigid start search ranks last of eight (the first four all
    // ended implausible: 577 mm mean vertex error when only those were checked).
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    std::mt19937 rng(1118);
    const auto [sol, err] = fit_benchmark_scan(m, lin, rng);
    INFO("mean vertex error " << err * 1e3 << " mm, " << sol.report.restarts << " restarts");
    CHECK(err < 0.01);
}

TEST_CASE("a scan fit gives the same result on any number of worker threads", "[fitting]") {
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, m.component_count());
    std::mt19937 rng(29);
    auto truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng), Eigen::Vector3d::Zero());
    fitting::Frame frame;
    simulation::CloudSpec spec;
    spec.points = 4000;
    frame.clouds.push_back(simulation::simulate_cloud(m, truth, spec, rng));
    ThreadPool one(1), three(3);
    const auto a = fitting::fit(lin, {frame}, fitting::FitOptions{}, nullptr, {}, &one);
    const auto b = fitting::fit(lin, {frame}, fitting::FitOptions{}, nullptr, {}, &three);
    REQUIRE(a.shape.size() == b.shape.size());
    for (std::size_t k = 0; k < a.shape.size(); ++k) CHECK(a.shape[k] == b.shape[k]);
    for (std::size_t j = 0; j < a.frames[0].pose.size(); ++j) CHECK(a.frames[0].pose[j].coeffs() == b.frames[0].pose[j].coeffs());
    CHECK(a.report.iterations == b.report.iterations);
}

TEST_CASE("the fitter rejects bad input with a message", "[fitting]") {
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, 10);
    auto status_of = [&](const std::vector<fitting::Frame>& frames, fitting::FitOptions o = {}) {
        try {
            fitting::fit(lin, frames, o);
        } catch (const Error& e) {
            CHECK(std::string(e.what()).find("fit") != std::string::npos);
            return e.status();
        }
        return SSC_OK;
    };
    CHECK(status_of({}) == SSC_ERROR_INVALID_ARGUMENT);
    fitting::Frame empty;
    CHECK(status_of({empty}) == SSC_ERROR_INVALID_ARGUMENT);
    fitting::Frame cloud;
    cloud.clouds.resize(1);
    CHECK(status_of({cloud}) == SSC_ERROR_INVALID_ARGUMENT);  // an empty cloud
    for (int i = 0; i < 20; ++i) cloud.clouds[0].points.emplace_back(0.01 * i, 0.1 * i, 0);
    cloud.clouds[0].points[3].x() = std::nan("");
    CHECK(status_of({cloud}) == SSC_ERROR_INVALID_ARGUMENT);
    cloud.clouds[0].points[3].x() = 1e300;  // finite, but no measurement (extents would overflow)
    CHECK(status_of({cloud}) == SSC_ERROR_INVALID_ARGUMENT);
    cloud.clouds[0].points[3].x() = 0;
    cloud.clouds[0].normals.resize(3, Eigen::Vector3d::UnitZ());
    CHECK(status_of({cloud}) == SSC_ERROR_INVALID_ARGUMENT);  // counts differ
    fitting::Frame lm;
    for (uint32_t l = 0; l < 3; ++l) lm.landmarks.push_back({l, Eigen::Vector3d(l, 0, 0), 1});
    lm.landmarks[1].landmark = 9999;
    CHECK(status_of({lm}) == SSC_ERROR_INVALID_ARGUMENT);
    lm.landmarks[1].landmark = 1;
    lm.landmarks[2].weight = -1;
    CHECK(status_of({lm}) == SSC_ERROR_INVALID_ARGUMENT);
    lm.landmarks[2].weight = 1;
    fitting::FitOptions bad;
    bad.landmark_sigma = 0;
    CHECK(status_of({lm}, bad) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(status_of({lm}) == SSC_OK);  // three landmarks are enough to run
}

TEST_CASE("the C API fits landmarks by name and reports through ssc_fitter", "[fitting][capi]") {
    ssc_model* model = nullptr;
    REQUIRE(ssc_model_load_default(nullptr, &model) == SSC_OK);
    const uint32_t V = ssc_model_vertex_count(model), J = ssc_model_joint_count(model), K = ssc_model_shape_count(model);
    const uint32_t L = ssc_model_landmark_count(model);
    // A known body made through the public API.
    ssc_body* body = nullptr;
    REQUIRE(ssc_body_create(model, nullptr, &body) == SSC_OK);
    std::vector<float> shape(K, 0.f);
    shape[0] = 1.2f, shape[1] = -0.8f, shape[3] = 0.5f;
    REQUIRE(ssc_body_set_shape(body, shape.data(), K) == SSC_OK);
    std::vector<float> axis_angle(3 * J, 0.f);
    uint32_t elbow = 0;
    REQUIRE(ssc_model_find_joint(model, "lowerarm_l", &elbow) == SSC_OK);
    axis_angle[3 * elbow + 2] = 0.8f;
    const float translation[3] = {0.2f, 0.f, 1.f};
    REQUIRE(ssc_body_set_pose_axis_angle(body, axis_angle.data(), J, translation) == SSC_OK);
    std::vector<float> truth(3 * V), landmarks(3 * L);
    REQUIRE(ssc_body_get_vertices(body, truth.data(), V, 0) == SSC_OK);
    REQUIRE(ssc_body_get_landmarks(body, landmarks.data(), L, 0) == SSC_OK);
    std::vector<const char*> names(L);
    for (uint32_t l = 0; l < L; ++l) REQUIRE(ssc_model_get_landmark_name(model, l, &names[l]) == SSC_OK);

    ssc_fitter_def def;
    ssc_fitter_def_init(&def, sizeof def);
    def.landmark_sigma = 0.005f;
    ssc_fitter* fitter = nullptr;
    REQUIRE(ssc_fitter_create(model, &def, &fitter) == SSC_OK);
    CHECK(def.fit_segments == 1u);  // the model's segment shape spaces join by default
    float out[3];
    CHECK(ssc_fitter_get_shape(fitter, out, 3) == SSC_ERROR_INVALID_ARGUMENT);  // not solved yet
    CHECK(ssc_fitter_get_segment_shape(fitter, 0, out, 3) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_fitter_solve(fitter, nullptr, nullptr, nullptr) == SSC_ERROR_INVALID_ARGUMENT);  // no frames
    const char* unknown[1] = {"Left Elbow Tip"};
    CHECK(ssc_fitter_add_landmarks_by_name(fitter, 0, unknown, landmarks.data(), nullptr, 1) == SSC_ERROR_NOT_FOUND);
    CHECK(std::string(ssc_last_error()).find("Left Elbow Tip") != std::string::npos);
    CHECK(ssc_fitter_add_landmarks_by_name(fitter, 1, names.data(), landmarks.data(), nullptr, L) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_fitter_frame_count(fitter) == 0);  // nothing added by the failures
    const char* twice[2] = {names[0], names[0]};
    CHECK(ssc_fitter_add_landmarks_by_name(fitter, 0, twice, landmarks.data(), nullptr, 2) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(ssc_last_error()).find("twice") != std::string::npos);
    CHECK(ssc_fitter_frame_count(fitter) == 0);
    REQUIRE(ssc_fitter_add_landmarks_by_name(fitter, 0, names.data(), landmarks.data(), nullptr, L) == SSC_OK);
    CHECK(ssc_fitter_frame_count(fitter) == 1);
    // A landmark the frame already holds, added again: refused (another frame may have it).
    CHECK(ssc_fitter_add_landmarks_by_name(fitter, 0, names.data() + 1, landmarks.data(), nullptr, 1) == SSC_ERROR_INVALID_ARGUMENT);

    // Cancelling from the progress callback.
    auto cancel = [](void*, uint32_t iteration, float) { return iteration >= 2 ? 1 : 0; };
    CHECK(ssc_fitter_solve(fitter, cancel, nullptr, nullptr) == SSC_ERROR_CANCELLED);

    ssc_fit_report report;
    report.struct_size = sizeof report;
    REQUIRE(ssc_fitter_solve(fitter, nullptr, nullptr, &report) == SSC_OK);
    CHECK(report.iterations > 0);
    CHECK(report.landmark_rms < 0.01f);
    std::vector<float> fitted(3 * V), fitted_shape(K);
    CHECK(ssc_fitter_get_vertices(fitter, 0, fitted.data(), V - 1, 0) == SSC_ERROR_BUFFER_TOO_SMALL);
    REQUIRE(ssc_fitter_get_vertices(fitter, 0, fitted.data(), V, 0) == SSC_OK);
    REQUIRE(ssc_fitter_get_shape(fitter, fitted_shape.data(), K) == SSC_OK);
    CHECK(ssc_fitter_get_pose(fitter, 1, nullptr, 0, nullptr, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
    std::vector<float> rotations(4 * J);
    float t[3], scale = 0;
    REQUIRE(ssc_fitter_get_pose(fitter, 0, rotations.data(), J, t, &scale) == SSC_OK);
    CHECK(scale == 1.f);
    double err = 0;
    for (uint32_t v = 0; v < V; ++v)
        err += std::sqrt(std::pow(fitted[3 * v] - truth[3 * v], 2) + std::pow(fitted[3 * v + 1] - truth[3 * v + 1], 2) +
                         std::pow(fitted[3 * v + 2] - truth[3 * v + 2], 2));
    err /= V;
    INFO("mean vertex error " << err * 1e3 << " mm; shape[0] " << fitted_shape[0]);
    CHECK(err < 0.01);
    // The fitted parameters reproduce the fitted surface through a body: the whole body's shape,
    // every segment's and the pose.
    REQUIRE(ssc_body_set_shape(body, fitted_shape.data(), K) == SSC_OK);
    const uint32_t segments = ssc_model_segment_count(model);
    REQUIRE(segments == 6);
    ssc_segment_info info;
    info.struct_size = sizeof info;
    for (uint32_t g = 0; g < segments; ++g) {
        REQUIRE(ssc_model_get_segment_info(model, g, &info) == SSC_OK);
        std::vector<float> coefficients(info.shape_count, -99.f);
        REQUIRE(ssc_fitter_get_segment_shape(fitter, g, coefficients.data(), info.shape_count) == SSC_OK);
        CHECK(std::all_of(coefficients.begin(), coefficients.end(), [](float c) { return std::isfinite(c) && std::abs(c) < 10; }));
        REQUIRE(ssc_body_set_segment_shape(body, g, coefficients.data(), info.shape_count) == SSC_OK);
    }
    std::vector<float> segment(info.shape_count);
    CHECK(ssc_fitter_get_segment_shape(fitter, segments, segment.data(), info.shape_count) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_fitter_get_segment_shape(fitter, 1, segment.data(), info.shape_count - 1) == SSC_ERROR_BUFFER_TOO_SMALL);
    CHECK(ssc_fitter_get_segment_shape(fitter, 1, nullptr, info.shape_count) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_fitter_get_segment_shape(nullptr, 1, segment.data(), info.shape_count) == SSC_ERROR_INVALID_ARGUMENT);
    REQUIRE(ssc_body_set_pose(body, rotations.data(), J, t) == SSC_OK);
    std::vector<float> again(3 * V);
    REQUIRE(ssc_body_get_vertices(body, again.data(), V, 0) == SSC_OK);
    double worst = 0;
    for (std::size_t i = 0; i < again.size(); ++i) worst = std::max(worst, double(std::abs(again[i] - fitted[i])));
    CHECK(worst < 1e-4);

    // Points: bad input is refused whole.
    std::vector<float> pts(3 * 20, 0.f);
    for (int i = 0; i < 20; ++i) pts[3 * i] = 0.01f * i;
    CHECK(ssc_fitter_add_points(fitter, 0, pts.data(), nullptr, nullptr, 10, 0) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(ssc_fitter_add_points(fitter, 0, pts.data(), nullptr, nullptr, 20, 6) == SSC_ERROR_INVALID_ARGUMENT);
    pts[7] = std::nanf("");
    CHECK(ssc_fitter_add_points(fitter, 0, pts.data(), nullptr, nullptr, 20, 0) == SSC_ERROR_INVALID_ARGUMENT);
    pts[7] = 1e30f;  // finite, but no measurement
    CHECK(ssc_fitter_add_points(fitter, 0, pts.data(), nullptr, nullptr, 20, 0) == SSC_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(ssc_last_error()).find("beyond") != std::string::npos);
    CHECK(ssc_fitter_point_count(fitter, 0) == 0);
    pts[7] = 0;
    REQUIRE(ssc_fitter_add_points(fitter, 0, pts.data(), nullptr, nullptr, 20, 0) == SSC_OK);
    CHECK(ssc_fitter_point_count(fitter, 0) == 20);
    CHECK(ssc_fitter_get_shape(fitter, fitted_shape.data(), K) == SSC_ERROR_INVALID_ARGUMENT);  // results dropped
    CHECK(ssc_fitter_clear(fitter) == SSC_OK);
    CHECK(ssc_fitter_frame_count(fitter) == 0);

    CHECK(ssc_fitter_create(nullptr, nullptr, &fitter) == SSC_ERROR_INVALID_ARGUMENT);
    ssc_fitter_destroy(fitter);
    ssc_fitter_destroy(nullptr);
    ssc_body_destroy(body);
    ssc_model_release(model);
}

TEST_CASE("a fitter's point residuals measure each scan point's distance to the fitted surface", "[fitting][capi]") {
    const Model& m = default_model().model();
    std::mt19937 rng(17);
    auto truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng, 0.3), Eigen::Vector3d::Zero());
    simulation::CloudSpec spec;
    spec.points = 6000;
    spec.outliers = 0;
    spec.noise = 0.002;
    auto cloud = simulation::simulate_cloud(m, truth, spec, rng);
    // Two points off the body by a known distance: 10 cm out along the surface normal of a point.
    const Eigen::Vector3d off = cloud.points[0] + 0.1 * cloud.normals[0];
    std::vector<float> pts, nrm;
    for (std::size_t i = 0; i < cloud.points.size(); ++i)
        for (int a = 0; a < 3; ++a) pts.push_back(float(cloud.points[i][a])), nrm.push_back(float(cloud.normals[i][a]));
    for (int a = 0; a < 3; ++a) pts.push_back(float(off[a])), nrm.push_back(float(cloud.normals[0][a]));
    const uint32_t n = uint32_t(pts.size() / 3);

    ssc_model* model = nullptr;
    REQUIRE(ssc_model_load_default(nullptr, &model) == SSC_OK);
    ssc_fitter* fitter = nullptr;
    REQUIRE(ssc_fitter_create(model, nullptr, &fitter) == SSC_OK);
    REQUIRE(ssc_fitter_add_points(fitter, 0, pts.data(), nrm.data(), nullptr, n, 0) == SSC_OK);
    std::vector<float> residuals(n, -1.f);
    CHECK(ssc_fitter_get_point_residuals(fitter, 0, residuals.data(), n) == SSC_ERROR_INVALID_ARGUMENT);  // not solved
    REQUIRE(ssc_fitter_solve(fitter, nullptr, nullptr, nullptr) == SSC_OK);
    CHECK(ssc_fitter_get_point_residuals(fitter, 0, residuals.data(), n - 1) != SSC_OK);  // too small
    CHECK(ssc_fitter_get_point_residuals(fitter, 1, residuals.data(), n) == SSC_ERROR_INVALID_ARGUMENT);  // no such frame
    REQUIRE(ssc_fitter_get_point_residuals(fitter, 0, residuals.data(), n) == SSC_OK);
    // In the order added: the scan's points lie within noise and model error of the fit, the one
    // put 10 cm out lies 10 cm off (less what the fit moved towards it: nothing, it is one point).
    std::vector<float> scan(residuals.begin(), residuals.end() - 1);
    for (float r : residuals) REQUIRE((std::isfinite(r) && r >= 0));
    std::nth_element(scan.begin(), scan.begin() + scan.size() / 2, scan.end());
    CHECK(scan[scan.size() / 2] < 0.004);
    CHECK(residuals.back() == Approx(0.1).margin(0.01));
    ssc_fitter_destroy(fitter);
    ssc_model_release(model);
}

TEST_CASE("depth images back-project onto the seen surface with normals towards the camera", "[fitting][depth]") {
    const Model& m = default_model().model();
    std::mt19937 rng(5);
    const auto truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng, 0.5), Eigen::Vector3d::Zero());
    simulation::DepthCameraSpec spec;
    spec.noise = 0;
    const Eigen::Vector3d eye(0.4, 1.1, 2.6), target(0, 0.9, 0);
    const auto cam = simulation::look_at(eye, target, spec);
    auto depth = simulation::render_depth(m, truth, cam, spec, rng);
    fitting::DepthView view;
    view.width = spec.width, view.height = spec.height, view.depth = depth.data(), view.camera = cam;
    const auto cloud = fitting::depth_to_cloud(view);
    REQUIRE(cloud.points.size() > 5000);
    REQUIRE(cloud.normals.size() == cloud.points.size());
    // Every point lies on the body (within the mesh's faceting) and faces the camera.
    const fitting::PointIndex index(truth.vertices);
    double mean = 0;
    std::size_t facing = 0;
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        double d2;
        const uint32_t v = index.nearest(cloud.points[i], &d2);
        mean += std::sqrt(d2);
        facing += cloud.normals[i].dot(eye - cloud.points[i]) > 0 && cloud.normals[i].dot(truth.normals[v]) > 0.5;
    }
    mean /= double(cloud.points.size());
    INFO("mean distance to the nearest vertex " << mean * 1e3 << " mm; facing " << facing << " of " << cloud.points.size());
    CHECK(mean < 0.008);  // vertices are about 1-2 cm apart: the nearest is rarely the foot point
    CHECK(double(facing) > 0.95 * double(cloud.points.size()));
    // A mask removes what it covers; depth limits remove what lies outside them.
    std::vector<uint8_t> mask(depth.size(), 1);
    for (uint32_t v = 0; v < spec.height / 2; ++v)
        for (uint32_t u = 0; u < spec.width; ++u) mask[v * spec.width + u] = 0;
    view.mask = mask.data();
    const auto lower = fitting::depth_to_cloud(view);
    CHECK(lower.points.size() < cloud.points.size());
    for (const auto& p : lower.points) CHECK((cam.rotation.transpose() * (p - cam.position)).y() > -0.01);
    view.mask = nullptr;
    view.max_depth = 0.5;
    CHECK_THROWS_AS(fitting::depth_to_cloud(view), Error);  // nothing within 0.5 m
    view.max_depth = 0;
    view.camera.fx = 0;
    CHECK_THROWS_AS(fitting::depth_to_cloud(view), Error);
    view.camera.fx = 525;
    view.camera.cy = std::nan("");
    CHECK_THROWS_AS(fitting::depth_to_cloud(view), Error);
}

TEST_CASE("front and back depth images fit a body through the C API", "[fitting][depth][capi]") {
    const Model& m = default_model().model();
    ssc_model* model = default_model().handle;
    std::mt19937 rng(8);
    const auto truth = simulation::make_body(m, simulation::random_shape(m, rng), simulation::random_pose(m, rng, 0.5), Eigen::Vector3d::Zero());
    simulation::DepthCameraSpec spec;
    ssc_fitter* fitter = nullptr;
    REQUIRE(ssc_fitter_create(model, nullptr, &fitter) == SSC_OK);
    for (const double side : {1.0, -1.0}) {
        const auto cam = simulation::look_at(Eigen::Vector3d(0, 1.0, 2.8 * side), Eigen::Vector3d(0, 1.0, 0), spec);
        const auto depth = simulation::render_depth(m, truth, cam, spec, rng);
        // 16-bit millimetres, as a sensor delivers them, rows padded to 1300 bytes.
        const std::size_t stride = 1300;
        std::vector<uint8_t> rows(stride * spec.height, 0xAB);
        for (uint32_t v = 0; v < spec.height; ++v)
            for (uint32_t u = 0; u < spec.width; ++u) {
                const uint16_t mm = uint16_t(std::lround(depth[v * spec.width + u] * 1000));
                std::memcpy(&rows[v * stride + 2 * u], &mm, 2);
            }
        float pose[16] = {0};
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) pose[4 * c + r] = float(cam.rotation(r, c));
            pose[12 + r] = float(cam.position[r]);
        }
        pose[15] = 1;
        ssc_depth_image_def img;
        ssc_depth_image_def_init(&img, sizeof img);
        img.width = spec.width, img.height = spec.height;
        img.samples = rows.data();
        img.row_stride = stride;
        img.fx = float(cam.fx), img.fy = float(cam.fy), img.cx = float(cam.cx), img.cy = float(cam.cy);
        img.camera_to_world = pose;
        // Bad input first: nothing is added.
        ssc_depth_image_def bad = img;
        bad.fx = 0;
        CHECK(ssc_fitter_add_depth_image(fitter, 0, &bad, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
        bad = img;
        bad.cx = std::nanf("");
        CHECK(ssc_fitter_add_depth_image(fitter, 0, &bad, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
        bad = img;
        bad.row_stride = 1279;
        CHECK(ssc_fitter_add_depth_image(fitter, 0, &bad, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
        bad = img;
        bad.samples = nullptr;
        CHECK(ssc_fitter_add_depth_image(fitter, 0, &bad, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
        float skewed[16];
        std::memcpy(skewed, pose, sizeof pose);
        skewed[0] *= 2;
        bad = img;
        bad.camera_to_world = skewed;
        CHECK(ssc_fitter_add_depth_image(fitter, 0, &bad, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
        bad = img;
        bad.format = ssc_depth_format(7);
        CHECK(ssc_fitter_add_depth_image(fitter, 0, &bad, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
        CHECK(ssc_fitter_add_depth_image(fitter, 0, nullptr, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
        CHECK(ssc_fitter_add_depth_image(fitter, 5, &img, nullptr) == SSC_ERROR_INVALID_ARGUMENT);
        const uint32_t before = ssc_fitter_point_count(fitter, 0);
        uint32_t added = 0;
        REQUIRE(ssc_fitter_add_depth_image(fitter, 0, &img, &added) == SSC_OK);
        CHECK(added > 5000);
        CHECK(ssc_fitter_point_count(fitter, 0) == before + added);
    }
    CHECK(ssc_fitter_frame_count(fitter) == 1);
    ssc_fit_report report;
    report.struct_size = sizeof report;
    REQUIRE(ssc_fitter_solve(fitter, nullptr, nullptr, &report) == SSC_OK);
    const uint32_t V = m.vertex_count();
    std::vector<float> fitted(3 * V);
    REQUIRE(ssc_fitter_get_vertices(fitter, 0, fitted.data(), V, 0) == SSC_OK);
    double err = 0;
    for (uint32_t v = 0; v < V; ++v) err += (Eigen::Vector3d(fitted[3 * v], fitted[3 * v + 1], fitted[3 * v + 2]) - truth.vertices[v]).norm();
    err /= V;
    INFO("mean vertex error " << err * 1e3 << " mm, point mean " << report.point_mean * 1e3 << " mm");
    CHECK(err < 0.012);
    ssc_fitter_destroy(fitter);
}

TEST_CASE("everyday poses lie within the joint limits and impossible ones outside", "[fitting][limits]") {
    const Model& m = default_model().model();
    const fitting::LinearModel lin(m, 1);
    const auto limits = anatomy::joint_limits(m);
    REQUIRE(limits.size() == m.joint_count());
    uint32_t limited = 0;
    for (const auto& l : limits) limited += l.limited;
    CHECK(limited == 21);  // 3 spine, neck, head, and 8 per side
    auto quat = [](const std::vector<float>& pose, uint32_t j) {
        return Eigen::Quaterniond(pose[4 * j + 3], pose[4 * j], pose[4 * j + 1], pose[4 * j + 2]);
    };
    std::mt19937 rng(12);
    for (int t = 0; t < 300; ++t) {
        const auto pose = simulation::random_pose(m, rng);
        for (uint32_t j = 0; j < m.joint_count(); ++j) {
            if (!limits[j].limited) continue;
            const Eigen::Vector3d c = anatomy::anatomical_angles(limits[j], quat(pose, j));
            INFO(m.data().skeleton.joint_names[j] << ": " << c.transpose() * 180 / M_PI << " degrees");
            CHECK((c.array() >= limits[j].lo.array()).all());
            CHECK((c.array() <= limits[j].hi.array()).all());
        }
    }
    // A rotation given about the body's axes at rest (as random_pose draws them).
    const auto& sk = m.data().skeleton;
    std::vector<Eigen::Matrix3d> W(m.joint_count());
    for (uint32_t j = 0; j < m.joint_count(); ++j) W[j] = sk.parents[j] < 0 ? lin.rest_orient[j] : W[uint32_t(sk.parents[j])] * lin.rest_orient[j];
    auto angles = [&](const char* joint, const Eigen::Vector3d& axis, double radians) {
        const uint32_t j = uint32_t(m.find_joint(joint));
        const Eigen::Matrix3d body = Eigen::AngleAxisd(radians, axis.normalized()).toRotationMatrix();
        return anatomy::anatomical_angles(limits[j], Eigen::Quaterniond(W[j].transpose() * body * W[j]));
    };
    const uint32_t calf_l = uint32_t(m.find_joint("calf_l")), calf_r = uint32_t(m.find_joint("calf_r"));
    CHECK(angles("calf_l", Eigen::Vector3d::UnitX(), 1.2).x() == Approx(1.2).margin(0.05));   // a knee bends backwards
    CHECK(angles("calf_r", Eigen::Vector3d::UnitX(), 1.2).x() == Approx(1.2).margin(0.05));
    CHECK(angles("calf_l", Eigen::Vector3d::UnitX(), -0.6).x() < limits[calf_l].lo.x());      // not forwards
    CHECK(angles("calf_r", Eigen::Vector3d::UnitX(), -0.6).x() < limits[calf_r].lo.x());
    // A thigh turned 120 degrees about the leg, either side.
    const uint32_t thigh_l = uint32_t(m.find_joint("thigh_l"));
    CHECK(std::abs(angles("thigh_l", Eigen::Vector3d::UnitY(), 2.1).y()) > limits[thigh_l].hi.y());
    CHECK(std::abs(angles("thigh_r", Eigen::Vector3d::UnitY(), -2.1).y()) > limits[thigh_l].hi.y());
    // Raising the left arm sideways is -z', on the right too (mirrored).
    CHECK(angles("upperarm_l", Eigen::Vector3d::UnitZ(), 1.0).z() == Approx(-1.0).margin(0.05));
    CHECK(angles("upperarm_r", Eigen::Vector3d::UnitZ(), -1.0).z() == Approx(-1.0).margin(0.05));
}

TEST_CASE("joint roles are model data: the file's, else the table of names, and the fit follows them", "[fitting][roles]") {
    const Model& m = default_model().model();
    const format::ModelData& d = m.data();
    // Training wrote the table's roles; a model without them gets the same from its names.
    REQUIRE(d.joint_roles.size() == m.joint_count());
    const std::vector<format::JointRole> table = anatomy::compute_joint_roles(d.skeleton);
    format::ModelData bare = d;
    bare.joint_roles.clear();
    const Model without(std::move(bare), nullptr);
    const std::vector<anatomy::JointRole> from_file = anatomy::joint_roles(m), from_names = anatomy::joint_roles(without);
    for (uint32_t j = 0; j < m.joint_count(); ++j) {
        INFO(d.skeleton.joint_names[j]);
        CHECK((table[j].part == d.joint_roles[j].part && table[j].side == d.joint_roles[j].side &&
               table[j].rotation_sigma == d.joint_roles[j].rotation_sigma && table[j].coarse == d.joint_roles[j].coarse &&
               table[j].limb_joint == d.joint_roles[j].limb_joint));
        CHECK((from_file[j].part == from_names[j].part && from_file[j].rotation_sigma == from_names[j].rotation_sigma &&
               from_file[j].limb_joint == from_names[j].limb_joint));
    }
    // Each arm and leg has its upper and middle joint for the limb search.
    for (auto part : {anatomy::BodyPart::Arm, anatomy::BodyPart::Leg})
        for (auto side : {anatomy::Side::Left, anatomy::Side::Right}) {
            const int64_t upper = anatomy::find_limb_joint(from_file, part, side, anatomy::LimbJoint::Upper);
            const int64_t middle = anatomy::find_limb_joint(from_file, part, side, anatomy::LimbJoint::Middle);
            REQUIRE(upper >= 0);
            CHECK(d.skeleton.parents[std::size_t(middle)] == upper);
        }
    // The fitter reads the roles, not the names: without limb joints in the file, no limb search,
    // and raised arms stay where the coarse stage leaves them: the fit is judged wrong and needs a
    // restart (the extremity start finds the arms then), where the limb search finds them at once.
    format::ModelData no_limbs = d;
    for (auto& r : no_limbs.joint_roles) r.limb_joint = 0;
    const Model searched_not(std::move(no_limbs), nullptr);
    std::mt19937 rng(23);
    const auto shape = simulation::random_shape(m, rng);
    const auto truth = simulation::make_body(m, shape, anatomy::named_pose(m, "arms_raised"), Eigen::Vector3d::Zero());
    double err[2];
    uint32_t restarts[2];
    for (int with = 0; with < 2; ++with) {
        const Model& used = with ? m : searched_not;
        const fitting::LinearModel lin(used, used.component_count());
        std::mt19937 scan_rng(5);
        const auto [sol, e] = fit_scan(used, lin, truth, 0.7, Eigen::Vector3d(0, 0.1, 1.5), scan_rng);
        err[with] = e, restarts[with] = sol.report.restarts;
    }
    INFO("arms raised: mean vertex error " << err[1] * 1e3 << " mm with the limb search (" << restarts[1] << " restarts), " << err[0] * 1e3
                                           << " mm without (" << restarts[0] << ")");
    CHECK(err[1] < 0.015);
    CHECK(restarts[1] == 0);
    CHECK(restarts[0] > 0);
}
