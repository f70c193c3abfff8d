#include "registration/register_scan.hpp"

#include "common/error.hpp"
#include "common/rigid.hpp"
#include "fitting/nearest.hpp"
#include "fitting/posed_surface.hpp"
#include "fitting/scan_normals.hpp"
#include "registration/landmark_agreement.hpp"
#include "registration/nonrigid.hpp"
#include "registration/scan_boundary.hpp"
#include "synthesis/body.hpp"

#include <Eigen/Geometry>

#include <chrono>
#include <memory>
#include <cmath>

namespace ssc::registration {

namespace {

// The stiffness and landmark weights fall by this factor after each round (the reference's), until
// the stiffness has fallen by kRelaxedRange.
constexpr double kRelax = 0.25;
constexpr double kRelaxedRange = 1000;
// A round's iterations stop when no vertex moved farther than this (metres).
constexpr double kSettled = 0.0005;
// Scans smaller than this are no body scan.
constexpr std::size_t kMinPoints = 100;
// The least share of the registered template within 20 mm of the scan for a registration to count.
constexpr double kLeastOnScan = 0.1;
// Metres: from the model start, landmarks this close to the hands (the wrists' styloids, any on
// the hands) pull in the model fit only, not in the deformation.
constexpr double kNearHands = 0.03;

// The stiffness of each round: relaxed by kRelax from `first` until it has fallen by kRelaxedRange,
// or that many rounds at the last value.
std::vector<double> round_factors(Schedule schedule) {
    std::vector<double> f;
    for (double x = 1; ; x *= kRelax) {
        f.push_back(x);
        if (1 / x >= kRelaxedRange) break;
    }
    if (schedule == Schedule::Constant) std::fill(f.begin(), f.end(), f.back());
    return f;
}

}  // namespace

// Why these rules: the head's hair and ears scan poorly (a wider gate, a tighter normal cone); the
// hands are often in another posture than the template's (a low data weight, stiffer), so the
// fingers follow the hand rather than stray onto nearby points.
RegionRule region_rule(const std::string& region) {
    if (region == "head") return {0.03, 45, 1.0, 2.0};
    if (region == "hands") return {0.02, 60, 0.3, 4.0};
    return {0.02, 60, 1.0, 1.0};
}

namespace {

// An even subsample of `most` points of a larger scan (kMaxScanPoints, register_scan.hpp); the scan itself otherwise.
const Scan& bounded(const Scan& given, std::size_t most, Scan& thinned) {
    const std::size_t n = given.cloud.points.size();
    if (n <= most) return given;
    const fitting::PointCloud& c = given.cloud;
    for (std::size_t i = 0; i < most; ++i) {
        const std::size_t k = std::size_t((unsigned __int128)i * n / most);
        thinned.cloud.points.push_back(c.points[k]);
        if (!c.normals.empty()) thinned.cloud.normals.push_back(c.normals[k]);
        if (!c.confidence.empty()) thinned.cloud.confidence.push_back(c.confidence[k]);
    }
    thinned.landmarks = given.landmarks;
    return thinned;
}

}  // namespace

namespace {


// The scan as the deformation sees it: normals where missing (oriented when they could be), the
// nearest-point index, the rim (holes are filled by the template's shape, not pulled to their edge).
struct ScanSurface {
    explicit ScanSurface(const Scan& scan)
        : points(scan.cloud.points),
          normals(scan.cloud.normals.empty() ? std::vector<Vector3d>(points.size(), Vector3d::Zero()) : scan.cloud.normals),
          index(points),
          oriented(fitting::estimate_missing_normals(points, index, normals)),
          rim(scan.triangles.empty() ? ScanRim(points, normals, index) : ScanRim(scan.triangles, points.size())) {}
    const std::vector<Vector3d>& points;
    std::vector<Vector3d> normals;
    const fitting::PointIndex index;
    const bool oriented;
    const ScanRim rim;
};

// The model start: the model fitted to the scan (out.fit), posed; refused when the fit failed or
// the landmarks disagree with it (landmark_off: the few it ignored).
std::vector<Vector3d> model_start(const fitting::LinearModel& lin, const Scan& scan, const ScanSurface& surface, const RegistrationOptions& options,
                                  const RegistrationProgress& progress, ThreadPool& workers, Body& body, Registration& out,
                                  std::vector<uint8_t>& landmark_off) {
    const format::ModelData& d = lin.model.data();
    const std::vector<Vector3d>& points = surface.points;
    const std::vector<Vector3d>& normals = surface.normals;
    std::vector<Vector3d> start;
    fitting::Frame frame;
    frame.landmarks = scan.landmarks;
    frame.clouds.push_back({points, normals, scan.cloud.confidence});
    const fitting::FitProgress fit_progress = [&](uint32_t iteration, double) {
        return !progress || progress("fit", iteration, options.fit.max_iterations);
    };
    out.fit = fitting::fit(lin, {frame}, options.fit, nullptr, fit_progress, &workers);
    if (out.fit.report.cancelled) fail(SSC_ERROR_CANCELLED, "registration cancelled");
    // A deformation started from a wrong fit ends wrong, and looks registered: refused. A
    // model without shape components (the template alone, bootstrap's weakest start) can
    // only place the template: it leaves the person's shape unexplained and bends joints
    // past their ranges to make up for it (spines 34-38 degrees on simulated MakeHuman
    // scans). Its fit is a rough start for the deformation, judged after it (acceptance).
    // Wrong landmarks (moved, exchanged sides) pull the fit or make it fail: fitted to the
    // points alone, the body says whether they were the cause, and which they are. Only
    // on these failure paths: it costs a second fit.
    auto landmarks_against_points_alone = [&](const std::string& prefix) {
        frame.landmarks.clear();
        const fitting::FitSolution alone = fitting::fit(lin, {frame}, options.fit, nullptr, fit_progress, &workers);
        if (alone.report.cancelled) fail(SSC_ERROR_CANCELLED, "registration cancelled");
        if (alone.report.frames.empty() || alone.report.frames[0].failed) return;
        std::vector<Vector3d> fitted;
        fitting::posed_surface(body, alone.frames[0], fitted);
        const LandmarkAgreement a = landmark_agreement(d, scan.landmarks, fitted);
        if (a.disagrees()) fail(SSC_ERROR_INVALID_ARGUMENT, prefix + a.describe(d, scan.landmarks));
    };
    const fitting::FrameReport* judged = out.fit.report.frames.empty() ? nullptr : &out.fit.report.frames[0];
    if (judged && judged->failed && lin.K > 0) {
        const std::string why = "register: the model fit to the scan failed (" + judged->problem_text + ")";
        if (!scan.landmarks.empty()) landmarks_against_points_alone(why + " with the landmarks given; ");
        fail(SSC_ERROR_INVALID_ARGUMENT, why + ": a registration started from it would be wrong; landmarks on the scan help a hard pose");
    }
    fitting::posed_surface(body, out.fit.frames[0], start);
    if (!scan.landmarks.empty() && lin.K > 0) {
        const LandmarkAgreement a = landmark_agreement(d, scan.landmarks, start);
        if (a.disagrees()) {
            landmarks_against_points_alone("register: ");
            fail(SSC_ERROR_INVALID_ARGUMENT, "register: " + a.describe(d, scan.landmarks));
        }
        landmark_off = a.off;  // a few: the fit ignored them; the deformation would pull the surface to them
    }
    out.report.fit_seconds = out.fit.report.seconds;
    return start;
}

// The template at rest aligned to the scan's landmarks (a similarity).
std::vector<Vector3d> rigid_start(const format::ModelData& d, const Scan& scan, Body& body, const fitting::FitState& rest) {
    std::vector<Vector3d> start;
    SSC_REQUIRE_ARG(scan.landmarks.size() >= 3, "register: the rigid initialisation needs at least 3 landmarks");
    fitting::posed_surface(body, rest, start);
    Eigen::Matrix3Xd src(3, scan.landmarks.size()), dst(3, scan.landmarks.size());
    for (std::size_t l = 0; l < scan.landmarks.size(); ++l) {
        src.col(Eigen::Index(l)) = point_on(start, fitting::landmark_point(d, scan.landmarks[l].landmark));
        dst.col(Eigen::Index(l)) = scan.landmarks[l].position;
    }
    const Similarity T = align_points(src, dst, true);
    for (Vector3d& v : start) v = T.scale * T.R * v + T.t;
    return start;
}

std::vector<Vector3d> rbf_start(const format::ModelData& d, const Scan& scan, const RegistrationOptions& options, Body& body, const fitting::FitState& rest) {
    std::vector<Vector3d> start;
    // The template at rest warped through its landmarks onto the scan's.
    SSC_REQUIRE_ARG(scan.landmarks.size() >= 4, "register: the rbf initialisation needs at least 4 landmarks");
    fitting::posed_surface(body, rest, start);
    std::vector<Vector3d> from, to;
    for (const auto& l : scan.landmarks) {
        from.push_back(point_on(start, fitting::landmark_point(d, l.landmark)));
        to.push_back(l.position);
    }
    const RbfWarp warp(std::move(from), to, options.rbf_kernel, options.rbf_scale);
    for (Vector3d& v : start) v = warp(v);
    return start;
}


// Each vertex's data weight is its share of the surface (a third of its triangles' area, over
// the mean): the data term then measures the surface, not the mesh. The template's face, hands
// and feet are meshed several times finer than its body, and equal weights per vertex let
// their many vertices each chase its own noisy scan point (a crumpled face).
std::vector<double> surface_shares(const std::vector<Vector3d>& start, const std::vector<uint32_t>& triangles, uint32_t V) {
    std::vector<double> area(V, 0.0);
    double total_area = 0;
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const double a = 0.5 * (start[triangles[t + 1]] - start[triangles[t]]).cross(start[triangles[t + 2]] - start[triangles[t]]).norm();
        for (int k = 0; k < 3; ++k) area[triangles[t + std::size_t(k)]] += a / 3;
        total_area += a;
    }
    for (double& a : area) a *= double(V) / std::max(total_area, 1e-12);
    return area;
}

// The landmarks the deformation pulls. From the model start, not those within kNearHands of
// the hands: the fit has placed the hands, and the wrists' landmarks pulled them about 1 mm
// along the surface (they have little data to hold them); the fit uses every landmark. From
// the rigid and rbf starts every one: nothing else brings the hands to their place
// (docs/registration.md).
void pulled_landmarks(const format::ModelData& d, const Scan& scan, const std::vector<Vector3d>& start, const BodyRegions& regions,
                      const std::vector<uint8_t>& landmark_off, bool from_model, std::vector<TemplatePoint>& marks, std::vector<LandmarkTarget>& landmarks) {
    std::vector<Vector3d> hand_vertices;
    if (from_model)
        for (uint32_t v = 0; v < uint32_t(start.size()); ++v)
            if (regions.of_vertex[v] >= 0 && regions.names[std::size_t(regions.of_vertex[v])] == "hands") hand_vertices.push_back(start[v]);
    for (std::size_t k = 0; k < scan.landmarks.size(); ++k) {
        const auto& l = scan.landmarks[k];
        if (landmark_off[k]) continue;
        const fitting::SurfacePoint p = fitting::landmark_point(d, l.landmark);
        const Vector3d at = point_on(start, p);
        bool near_hands = false;
        for (const Vector3d& h : hand_vertices) near_hands |= (h - at).squaredNorm() < kNearHands * kNearHands;
        if (near_hands) continue;
        marks.push_back(p);
        landmarks.push_back({p, l.position});
    }
}

// The deformation of the started template onto the scan: per-vertex region rules and the edges'
// stiffness, the landmarks it pulls, each vertex's share of the surface, the correspondences, and
// the rounds of relaxed stiffness.
class Deformation {
public:
    Deformation(const format::ModelData& d, const Scan& scan, const ScanSurface& surface, const std::vector<Vector3d>& start,
                const std::vector<uint8_t>& landmark_off, const RegistrationOptions& options, ThreadPool& workers)
        : surface_(surface), options_(options), workers_(workers), V_(uint32_t(start.size())), regions_(body_regions(d)),
          triangles_(d.mesh.triangles.begin(), d.mesh.triangles.end()), edges_(mesh_edges(triangles_, V_)) {
        for (const auto& name : regions_.names) rules_.push_back(region_rule(name));
        std::vector<double> edge_stiffness;
        for (const auto& e : edges_) edge_stiffness.push_back(0.5 * (rule_of(e[0]).stiffness + rule_of(e[1]).stiffness));
        pulled_landmarks(d, scan, start, regions_, landmark_off, options.initialisation == Initialisation::Model, marks_, landmarks_);
        system_ = std::make_unique<NonrigidSystem>(start, edges_, edge_stiffness, marks_, options.gamma);
        area_ = surface_shares(start, triangles_, V_);
        targets_.assign(V_, Vector3d::Zero());
        weights_.assign(V_, 0.0);
    }

    // Correspondences: each deformed vertex's nearest scan point, when it is compatible and not on
    // the scan's rim (holes are filled by the template's shape). Which vertices have data (the
    // weights) is settled at a round's first iteration, so the round's later iterations reuse its
    // factorisation (nonrigid.hpp); a vertex whose new nearest point fails the test there keeps its
    // last target.
    void correspond(const std::vector<Vector3d>& x, bool settle_weights) {
        const std::vector<Vector3d> n = vertex_normals(x, triangles_);
        const std::vector<Vector3d>& points = surface_.points;
        const std::vector<Vector3d>& normals = surface_.normals;
        const uint32_t V = V_;
        constexpr std::size_t kChunks = 32;
        workers_.parallel_for(kChunks, [&](std::size_t c, unsigned) {
            for (uint32_t v = uint32_t(c * V / kChunks); v < uint32_t((c + 1) * V / kChunks); ++v) {
                const RegionRule& r = rule_of(v);
                double d2;
                const uint32_t q = surface_.index.nearest(x[v], &d2);
                const double dot = normals[q].squaredNorm() > 0 ? normals[q].dot(n[v]) : 1.0;
                const bool ok = d2 <= r.max_distance * r.max_distance && !surface_.rim(q) &&
                                (surface_.oriented ? dot : std::abs(dot)) >= std::cos(r.max_angle * M_PI / 180);
                if (settle_weights) weights_[v] = ok ? r.data_weight * area_[v] : 0.0;
                // The point of the scan's tangent plane at q nearest the vertex: a sparse scan's
                // nearest sample lies up to half a spacing aside, and would pull the vertex along the
                // surface towards it.
                const Vector3d& nq = normals[q];
                const Vector3d target = nq.squaredNorm() > 0 ? Vector3d(x[v] - (x[v] - points[q]).dot(nq) * nq) : points[q];
                if (ok || settle_weights) targets_[v] = target;
            }
        });
    }

    // With landmarks, a round without data first brings them into place; then the rounds of
    // relaxed stiffness, each iterated until no vertex moves (kSettled). Returns the deformed
    // template; counts the rounds and solves in `report`.
    template <class Tick>
    std::vector<Vector3d> run(const Tick& tick, RegistrationReport& report) {
        NonrigidSystem& system = *system_;
        Eigen::MatrixX3d X = system.identity();
        if (!landmarks_.empty() && options_.landmarks > 0) {
            std::fill(weights_.begin(), weights_.end(), 0.0);
            system.factorize({0.0, options_.stiffness, options_.landmarks}, weights_, landmarks_, &workers_);
            X = system.solve(targets_, landmarks_, X, &workers_);
            ++report.solves;
        }
        const std::vector<double> factors = round_factors(options_.schedule);
        for (std::size_t round = 0; round < factors.size(); ++round) {
            tick("deform", uint32_t(round), uint32_t(factors.size()));
            const EnergyWeights k{1.0, options_.stiffness * factors[round], options_.landmarks * factors[round]};
            std::vector<Vector3d> x = system.deformed(X);
            for (uint32_t it = 0; it < options_.max_iterations; ++it) {
                correspond(x, it == 0);
                if (it == 0) system.factorize(k, weights_, landmarks_, &workers_);
                X = system.solve(targets_, landmarks_, X, &workers_);
                ++report.solves;
                const std::vector<Vector3d> next = system.deformed(X);
                double moved = 0;
                for (uint32_t v = 0; v < V_; ++v) moved = std::max(moved, (next[v] - x[v]).squaredNorm());
                x = next;
                if (moved < kSettled * kSettled) break;
            }
            ++report.rounds;
        }
        tick("deform", uint32_t(factors.size()), uint32_t(factors.size()));
        return system.deformed(X);
    }

    const std::vector<double>& weights() const { return weights_; }
    const std::vector<uint32_t>& triangles() const { return triangles_; }
    const BodyRegions& regions() const { return regions_; }
    std::size_t pulled() const { return landmarks_.size(); }

private:
    const RegionRule& rule_of(uint32_t v) const { return regions_.of_vertex[v] < 0 ? other_ : rules_[std::size_t(regions_.of_vertex[v])]; }

    const ScanSurface& surface_;
    const RegistrationOptions& options_;
    ThreadPool& workers_;
    const uint32_t V_;
    const BodyRegions regions_;
    std::vector<RegionRule> rules_;
    const RegionRule other_ = region_rule("");
    const std::vector<uint32_t> triangles_;
    const std::vector<std::array<uint32_t, 2>> edges_;
    std::vector<TemplatePoint> marks_;
    std::vector<LandmarkTarget> landmarks_;
    std::unique_ptr<NonrigidSystem> system_;
    std::vector<double> area_;
    std::vector<Vector3d> targets_;
    std::vector<double> weights_;
};

}  // namespace

void check_options(const RegistrationOptions& o) {
    SSC_REQUIRE_ARG(std::isfinite(o.stiffness) && o.stiffness > 0 && o.stiffness <= 1e6, "register: stiffness must be in (0, 1e6]");
    SSC_REQUIRE_ARG(std::isfinite(o.landmarks) && o.landmarks >= 0 && o.landmarks <= 1e6, "register: landmark weight must be in [0, 1e6]");
    SSC_REQUIRE_ARG(std::isfinite(o.gamma) && o.gamma > 0 && o.gamma <= 1e3, "register: gamma must be in (0, 1e3]");
    SSC_REQUIRE_ARG(o.max_iterations >= 1 && o.max_iterations <= 100, "register: max_iterations must be 1 to 100");
    SSC_REQUIRE_ARG(o.max_scan_points >= 1000, "register: max_scan_points must be at least 1000");
    SSC_REQUIRE_ARG(o.initialisation == Initialisation::Model || o.initialisation == Initialisation::Rigid || o.initialisation == Initialisation::Rbf,
                    "register: unknown initialisation");
    SSC_REQUIRE_ARG(std::isfinite(o.rbf_scale) && o.rbf_scale > 0 && o.rbf_scale <= 10, "register: rbf_scale must be in (0, 10] metres");
    SSC_REQUIRE_ARG(o.rbf_kernel == RbfKernel::ThinPlate || o.rbf_kernel == RbfKernel::Multiquadric || o.rbf_kernel == RbfKernel::Gaussian,
                    "register: unknown rbf kernel");
    SSC_REQUIRE_ARG(o.schedule == Schedule::Relaxed || o.schedule == Schedule::Constant, "register: unknown schedule");
}

void check_scan(const fitting::PointCloud& cloud, const std::vector<uint32_t>& triangles) {
    fitting::validate_cloud(cloud, "register: scan");
    SSC_REQUIRE_ARG_S(cloud.points.size() >= kMinPoints, "register: the scan has " << cloud.points.size() << " points; a body scan needs at least " << kMinPoints);
    fitting::validate_spread({&cloud.points}, "register: the scan");
    SSC_REQUIRE_ARG(triangles.size() % 3 == 0, "register: the scan's triangles need 3 indices each");
    for (uint32_t i : triangles) SSC_REQUIRE_ARG_S(i < cloud.points.size(), "register: a scan triangle index (" << i << ") is out of range");
}

Registration register_scan(const fitting::LinearModel& lin, const Scan& scan, const RegistrationOptions& options,
                           const RegistrationProgress& progress, ThreadPool* pool) {
    check_scan(scan.cloud, scan.triangles);
    for (std::size_t l = 0; l < scan.landmarks.size(); ++l)
        fitting::validate_landmark(lin.model.data(), scan.landmarks[l], "register: landmark " + std::to_string(l));
    check_options(options);
    return register_checked_scan(lin, scan, options, progress, pool);
}

Registration register_checked_scan(const fitting::LinearModel& lin, const Scan& given, const RegistrationOptions& options,
                                   const RegistrationProgress& progress, ThreadPool* pool) {
    SSC_REQUIRE_ARG(options.max_scan_points >= 1000, "register: max_scan_points must be at least 1000");
    Scan thinned;
    const Scan& scan = bounded(given, options.max_scan_points, thinned);
    const auto t0 = std::chrono::steady_clock::now();
    ThreadPool inline_pool(1);
    ThreadPool& workers = pool ? *pool : inline_pool;
    const Model& model = lin.model;
    const format::ModelData& d = model.data();
    const uint32_t V = model.vertex_count();
    auto tick = [&](const char* stage, uint32_t done, uint32_t total) {
        if (progress && !progress(stage, done, total)) fail(SSC_ERROR_CANCELLED, "registration cancelled");
    };

    // The scan: normals where missing, its rim.
    const ScanSurface surface(scan);
    const std::vector<Vector3d>& points = surface.points;
    const std::vector<Vector3d>& normals = surface.normals;
    const fitting::PointIndex& index = surface.index;
    const bool oriented = surface.oriented;

    if (!scan.landmarks.empty()) require_landmarks_on_scan(d, scan.landmarks, index);

    // The start: the template placed, posed and shaped by the initialisation.
    Registration out;
    std::vector<uint8_t> landmark_off(scan.landmarks.size(), 0);  // left out of the deformation
    std::vector<Vector3d> start;
    Body body(model, nullptr);
    body.set_pool(&workers);
    fitting::FitState rest;
    rest.shape.assign(lin.K, 0.0);
    rest.pose.assign(lin.J, Eigen::Quaterniond::Identity());
    switch (options.initialisation) {
        case Initialisation::Model: start = model_start(lin, scan, surface, options, progress, workers, body, out, landmark_off); break;
        case Initialisation::Rigid: start = rigid_start(d, scan, body, rest); break;
        case Initialisation::Rbf: start = rbf_start(d, scan, options, body, rest); break;
    }

    // The deformation, round by round, then where every vertex ended.
    Deformation deformation(d, scan, surface, start, landmark_off, options, workers);
    out.vertices = deformation.run(tick, out.report);
    deformation.correspond(out.vertices, true);
    out.valid.resize(V);
    for (uint32_t v = 0; v < V; ++v) out.valid[v] = deformation.weights()[v] > 0, out.report.valid += out.valid[v];
    const std::vector<uint32_t>& triangles = deformation.triangles();
    const BodyRegions& regions = deformation.regions();
    out.report.quality = registration_quality(out.vertices, triangles, vertex_normals(out.vertices, triangles), regions.of_vertex,
                                              regions.names, points, normals, oriented, index, workers);
    // A registration that lies mostly off its scan found no person there (two clusters of points
    // once "registered" with 3 % of the template within 20 mm; a front view alone gives 45 %).
    const double on_scan = out.report.quality.below[3];
    if (on_scan < kLeastOnScan)
        fail(SSC_ERROR_INVALID_ARGUMENT, "register: only " + std::to_string(int(std::lround(100 * on_scan))) +
                                             " % of the registered template lies within 20 mm of the scan: it missed the person (not a body scan, "
                                             "or one the start cannot reach)");
    out.report.scan_points = scan.cloud.points.size();
    out.report.scan_points_given = given.cloud.points.size();
    out.report.landmarks = scan.landmarks.size();
    out.report.deformation_landmarks = deformation.pulled();
    out.report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

}  // namespace ssc::registration
