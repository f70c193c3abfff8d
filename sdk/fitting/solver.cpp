// The fitter: see solver.hpp for the method. Parameters of all frames form one vector: the shared
// shape first, then each frame's rotations, translation and log scale (kinematics.hpp layout).
#include "fitting/solver.hpp"
#include "fitting/arrow_system.hpp"
#include "fitting/explained.hpp"
#include "fitting/hand_search.hpp"
#include "fitting/limb_search.hpp"
#include "fitting/rigid_start.hpp"
#include "fitting/robust.hpp"
#include "fitting/scan_normals.hpp"

#include "common/error.hpp"
#include "common/rigid.hpp"
#include "anatomy/hand_closure.hpp"
#include "anatomy/joint_limits.hpp"
#include "anatomy/joint_roles.hpp"
#include "anatomy/named_poses.hpp"
#include "fitting/nearest.hpp"
#include "fitting/normal_equations.hpp"
#include "fitting/posed_surface.hpp"
#include "synthesis/shape_range.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <random>

namespace ssc::fitting {

namespace {

using Eigen::MatrixXd;
using Eigen::Quaterniond;
using Eigen::VectorXd;

// Landmarks beyond this many sigmas count linearly (Huber): a misplaced landmark pulls, but boundedly.
constexpr double kHuber = 2.0;
// Model-to-scan pairs: how far (a fraction of the stage's gate) the scan point's own nearest model
// point may lie from the vertex (find_frame_pairs).
constexpr double kReciprocal = 0.5;
// A start candidate whose short coarse fit ends with pose priors above this is implausible (one
// joint 10 degrees past its limit costs about 38; plausible fits stay near 100 or below).
constexpr double kImplausiblePose = 300;
// A whole fit ending with pose priors above this is implausible, and a single frame's fit from the
// automatic start is then redone from the start search's other candidates, at most kMaxRestarts
// times (see run()). Of 670 benchmark fits (scan, front depth, front and back depth, trials 0-139;
// 250 more scans) all but two ended between 3 and 27; those two, forced onto a body of the other
// way round, near 300. An upside-down fit seen on the way ended at 98.
constexpr double kImplausibleFit = 50;
constexpr uint32_t kMaxRestarts = 2;
// A stage's plateau (see run_stage): relative gain, and iterations without it (Stage::stall).
constexpr double kPlateau = 2e-3;
constexpr uint32_t kStall = 3;
// Iterations of the polish stage (see run()).
constexpr uint32_t kPolish = 2;
// A limb that gained this fraction of the measure in the limb search has the limbs searched
// before it searched again (see fit_stages()). Chosen on the benchmark (scan, front depth, front
// and back depth; trials 0-59, checked on 60-139): any threshold from 0.05 to 0.3 fixed the same
// failures of the front depth images (an arm left on the thigh of a raised leg: 91 and 38 mm mean
// vertex error to 5); 0.3 searches again least often. Searching all four limbs again instead gave
// the same mean errors over 140 trials each (scan 2.50 against 2.48 mm, front 3.56 / 3.57, front
// and back 1.81 / 1.83) but also when the first limb was the one that moved. Searching again after
// every search took 35 to 60 ms more per fit and made two fits worse (2 to 10 and 12 mm).
constexpr double kResweep = 0.3;

// Empty shells of cells the scan grid records around each cell (GridIndex::index_empty_space):
// 8 cm: the limb search's model cap and the fine stage's gate (wider queries still skip these).
constexpr int kEmptyShells = 4;

// The start search's grid over a scan: 5 cm cells, empty space indexed out to kStartReach. A
// query far from the scan then starts at the shell of its nearest points (a k-d tree over the
// scan, which served these queries before, took 9 ms to build on one thread).
constexpr double kStartCell = 0.05;
constexpr int kStartShells = int(kStartReach / kStartCell) + 1;

// The normal equations' rows summed at once (evaluate()): 32 MB. One frame's fit (about 6,000
// groups of 3 rows, 80 columns or fewer) stays within one batch; many frames are summed a few at a time.
constexpr std::size_t kBatchDoubles = std::size_t(4) << 20;

// A scan point farther than this from the fitted model is unexplained (unexplained_share()). A
// one-frame fit leaving more than kRetryUnexplained of its scan unexplained is redone from the next
// start candidates (restart_if_implausible()); one leaving more than kFailedUnexplained is reported
// as not converged (FitReport). On the benchmark's scans (1 % outliers, 20 % holes; 30 trials) the
// share ended at 1.4 % or less, on front depth images at 0; retrying from 3 % rather than 5 % found
// two more of the hard poses' failures (bench --scenario poses) and flagged no good fit.
constexpr double kUnexplainedDistance = 0.05;
// An unexplained point counts when it lies on a surface: this many other scan points within this
// radius (metres). A body scan of 20,000 points has about 30 within 3 cm of each point, one of 6,000
// about 9; uniform clutter around a body (1 to 8 % of the points) has almost none.
constexpr std::size_t kSurfaceNeighbours = 3;
constexpr double kSurfaceRadius = 0.03;
constexpr double kRetryUnexplained = 0.03;
constexpr double kFailedUnexplained = 0.10;

// The poses the start search tries besides the rest pose (anatomy/named_poses.cpp): scans of
// people crouching, bent forward or seated have other principal axes than a standing body's, and
// a fit started from the rest pose ended upside down or standing (hard poses of the benchmark).
constexpr const char* kStartPoses[] = {"sitting", "crouching", "bending_forward"};
// Start candidates that get a short coarse fit at most (the best two always; more while those end
// implausible).
constexpr std::size_t kMaxShortFits = 8;

// Scan points and model points explained() scores (each a fixed random sample).
constexpr std::size_t kExplainedSamples = 1000;

// Joint limits are soft walls: beyond a limit the cost grows as (excess / kLimitSigma)^2 / 2, so
// 10 degrees past a limit costs as much as 75 scan points each 3 sigma off.
constexpr double kLimitSigma = 0.02;
// A stage, correspondence search or evaluation over every frame rather than one (frame_only).
constexpr uint32_t kAllFrames = 0xFFFFFFFFu;
// Levenberg-Marquardt damping (run_stage): the start of each stage, the factor a rejected step
// multiplies it by and an accepted one divides it by, its floor, and the steps tried per iteration.
constexpr double kInitialDamping = 1e-3, kDampingUp = 10, kDampingDown = 3, kMinDamping = 1e-7;
constexpr int kDampedAttempts = 8;

Matrix3d skew(const Vector3d& a) {
    Matrix3d m;
    m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
    return m;
}

Vector3d log_rotation(const Quaterniond& q) {
    const Eigen::AngleAxisd aa(q);
    return aa.angle() * aa.axis();
}

// Inverse of the left Jacobian of SO(3): d log(exp(d) exp(r)) / d d at d = 0.
Matrix3d inverse_left_jacobian(const Vector3d& r) {
    const double t = r.norm();
    const Matrix3d K = skew(r);
    if (t < 1e-6) return Matrix3d::Identity() - 0.5 * K + K * K / 12.0;
    return Matrix3d::Identity() - 0.5 * K + (1.0 / (t * t) - (1.0 + std::cos(t)) / (2.0 * t * std::sin(t))) * K * K;
}


SurfacePoint landmark_point(const format::ModelData& d, uint32_t l) {
    const auto& lm = d.landmarks[l];
    SurfacePoint p;
    if (lm.vertex != format::kNone) {
        p.vertex[0] = lm.vertex;
        return p;
    }
    for (int i = 0; i < 3; ++i) {
        p.vertex[i] = d.mesh.triangles[3 * std::size_t(lm.triangle) + i];
        p.weight[i] = lm.barycentric[i];
    }
    return p;
}

// One correspondence between the model surface and a measured point.
struct Pair {
    SurfacePoint model;
    Vector3d target, normal;  // normal: unit, or zero for point-to-point only
    double weight;            // confidence
};

// One residual block of the data: a landmark (Huber on the distance) or a correspondence
// (point_plane). scale = sqrt(weight) / sigma.
struct Block {
    uint32_t frame;
    const SurfacePoint* point;
    const Vector3d* target;
    const Vector3d* normal;  // null for a landmark
    double scale;
};

// Coarse-to-fine stages: what moves, how far correspondences may reach, how robust the loss is.
struct Stage {
    uint32_t iterations;
    bool body_joints, all_joints;  // rigid only when both are false
    uint32_t components;
    double max_distance;  // metres, correspondence gate
    double gm_scale;      // Geman-McClure scale in sigmas
    double min_normal_dot;
    double point_fraction;  // of max_points
    double tolerance = 1e-5;  // converged when a step lowers the cost by less than this fraction
    // Scan-to-model correspondences against every vertex, or (coarse stages) against the
    // area-sampled subset only: a tree a quarter the size, and coarse steps need no more.
    bool dense_model = false;
    // Iterations in a row without a gain of kPlateau that end the stage. The fine stage starts
    // close, with dense and steady correspondences: a third such iteration there did not change
    // the benchmark's errors and cost a tenth of the fit's time.
    uint32_t stall = kStall;
};

// The stages of a fit, coarse to fine (Solver::run): each a function, so its settings have names.
// Rigid: translation, rotation (and scale) only. A given start may be off by tens of centimetres
// at the head: the stage then reaches far with a wide loss; after the automatic start search it
// stays close.
Stage rigid_stage(uint32_t iterations, bool given_start) {
    Stage s{};
    s.iterations = iterations;
    s.body_joints = s.all_joints = false;
    s.components = 0;
    s.max_distance = given_start ? 1.0 : 0.3;
    s.gm_scale = given_start ? 40.0 : 10.0;
    s.min_normal_dot = 0.0;
    s.point_fraction = 0.25;
    s.tolerance = 1e-3;
    return s;
}

// Coarse: the trunk and limbs (not wrists, fingers, toes) and the first few shape components.
Stage coarse_stage(uint32_t iterations, uint32_t components) {
    Stage s{};
    s.iterations = iterations;
    s.body_joints = true;
    s.all_joints = false;
    s.components = components;
    s.max_distance = 0.10;
    s.gm_scale = 6.0;
    s.min_normal_dot = 0.3;
    s.point_fraction = 0.5;
    s.tolerance = 1e-4;
    return s;
}

// Fine: every joint and component, dense correspondences, on half the points until the first
// iteration without a gain; then the polish, the same on all of them. The fine stage's first steps
// (shape components 11 to 50 joining, the wrists and fingers free) need no more, and the last steps
// get the full accuracy. Against the whole fine stage on all points (benchmark, 30 trials): a tenth
// less CPU time, mean errors up to 0.2 mm higher (scan 2.18 against 2.04 mm).
Stage fine_stage(uint32_t iterations, uint32_t components, bool polish) {
    Stage s{};
    s.iterations = iterations;
    s.body_joints = s.all_joints = true;
    s.components = components;
    s.max_distance = 0.04;
    s.gm_scale = 4.0;
    s.min_normal_dot = 0.5;
    s.point_fraction = polish ? 1.0 : 0.5;
    s.tolerance = 1e-5;
    s.dense_model = true;
    s.stall = polish ? 2 : 1;
    return s;
}

struct FrameData {
    std::vector<SurfacePoint> landmark_points;
    std::vector<Vector3d> landmark_targets;
    std::vector<double> landmark_weights;
    std::vector<Vector3d> points, normals;  // all clouds merged; normals zero where unknown
    std::vector<double> confidence;
    bool oriented = true;  // normals known with their sign
    GridIndex scan_grid{0.02};              // for the fit's queries (all within a gate or a cap)
    GridIndex start_grid{kStartCell};        // for the start search's (CloudView::coarse_grid); built when needed
    std::unique_ptr<PointIndex> scan_index;  // for normal estimation; built when needed
    std::vector<uint32_t> scan_sample;  // random order of scan points; a prefix is used
    std::vector<Pair> pairs;
};

class Solver {
public:
    Solver(const LinearModel& lin, const std::vector<Frame>& frames, const FitOptions& o, ThreadPool* pool)
        : lin_(lin), o_(o), F_(uint32_t(frames.size())), K_(lin.K), B_(3 * lin.J + 4), body_(lin.model, nullptr),
          pool_(pool ? pool : &inline_pool_) {
        const auto& d = lin.model.data();
        body_.set_pool(pool_);
        std::mt19937 rng(o.seed);
        frames_.resize(F_);
        for (uint32_t f = 0; f < F_; ++f) {
            auto& fd = frames_[f];
            for (const auto& l : frames[f].landmarks) {
                fd.landmark_points.push_back(landmark_point(d, l.landmark));
                fd.landmark_targets.push_back(l.position);
                fd.landmark_weights.push_back(l.weight);
            }
            for (const auto& c : frames[f].clouds) {
                for (std::size_t i = 0; i < c.points.size(); ++i) {
                    fd.points.push_back(c.points[i]);
                    fd.normals.push_back(c.normals.empty() ? Vector3d::Zero() : c.normals[i]);
                    fd.confidence.push_back(c.confidence.empty() ? 1.0 : c.confidence[i]);
                }
            }
            if (!fd.points.empty()) {
                fd.scan_grid.build(fd.points);
                fd.scan_grid.index_empty_space(kEmptyShells, *pool_);
                estimate_missing_normals(fd);
                fd.scan_sample.resize(fd.points.size());
                for (uint32_t i = 0; i < fd.scan_sample.size(); ++i) fd.scan_sample[i] = i;
                std::shuffle(fd.scan_sample.begin(), fd.scan_sample.end(), rng);
            }
            kin_.emplace_back(lin);
        }
        for (const auto& name : d.skeleton.joint_names) {
            const anatomy::JointRole role = anatomy::joint_role(name);
            joint_sigma_.push_back(role.rotation_sigma);
            coarse_joint_.push_back(role.coarse);
        }
        // The fingers' rotation vectors at closure 1: at closure c the prior's centre is c times
        // that (each finger segment turns about a fixed axis).
        closed_fingers_.assign(lin.J, Vector3d::Zero());
        hand_of_joint_.assign(lin.J, -1);
        for (int hand = 0; hand < 2; ++hand)
            for (const auto& r : anatomy::hand_closure(lin.model, hand == 0 ? 'l' : 'r', 1.0)) {
                closed_fingers_[r.joint] = log_rotation(r.rotation);
                hand_of_joint_[r.joint] = int8_t(hand);
            }
        if (o.joint_limits) limits_ = lin.limits;
        bool any_points = false;
        for (const auto& fd : frames_) any_points |= !fd.points.empty();
        if (any_points) sample_vertices(rng);
        posed_.resize(lin.V);
        posed_normals_.resize(lin.V);
    }

    uint32_t parameters() const { return K_ + F_ * B_; }

    // refine: start from `start` with the fine stages only (the joint refinement of frames fitted
    // one by one, see fit()).
    FitSolution run(const std::vector<FitState>* start, const FitProgress& progress, std::chrono::steady_clock::time_point t0,
                    bool refine = false) {
        FitSolution sol;
        shape_.assign(K_, 0.0);
        states_.assign(F_, kin_[0].zero_state());
        if (start && !o_.auto_start) {
            for (uint32_t f = 0; f < F_; ++f) states_[f] = (*start)[f];
            for (uint32_t k = 0; k < K_ && k < (*start)[0].shape.size(); ++k)
                shape_[k] = within_shape_range((*start)[0].shape[k]);
            for (auto& s : states_) s.shape.resize(K_, 0.0);
        } else {
            for (uint32_t f = 0; f < F_; ++f) states_[f] = initial_state(f);
            // A single frame keeps the shape its start search fitted (several frames each fitted
            // their own; they start from the mean).
            if (F_ == 1 && searched_frames_ == 1) shape_ = states_[0].shape;
        }
        const uint32_t total = std::max<uint32_t>(o_.max_iterations, 3);
        const bool given_start = start && !o_.auto_start;
        // Stage budgets: a fifth rigid, a third coarse, kPolish (when there is room) the polish, the
        // rest fine.
        const uint32_t n0 = std::max<uint32_t>(1, total / 5), n1 = std::max<uint32_t>(1, total / 3);
        const uint32_t later = total - n0 - n1;  // at least 1: the fine stage keeps one
        const uint32_t n2 = later - std::min(kPolish, later - 1);
        const Stage stages[4] = {rigid_stage(n0, given_start), coarse_stage(n1, std::min<uint32_t>(K_, 10)),
                                 fine_stage(n2, K_, false), fine_stage(total - n0 - n1 - n2, K_, true)};
        bool cancelled = false;
        uint32_t iteration = 0;
        // Frames whose start search ended with a short coarse fit need no rigid stage.
        const int first_stage = refine ? 2 : searched_frames_ == F_ ? 1 : 0;
        bool converged = fit_stages(stages, first_stage, progress, iteration, cancelled, &sol.report.initial_cost);
        if (F_ == 1 && searched_frames_ == 1 && !cancelled)
            converged = restart_if_implausible(stages, progress, iteration, cancelled, sol.report.restarts, converged);
        update_kinematics();
        // Report on the final state with the final stage's rules.
        const Stage& last = stages[3];
        find_pairs(last);
        sol.report.final_cost = evaluate(last, nullptr, nullptr);
        double lm2 = 0, pd = 0;
        std::size_t nl = 0, np = 0, accepted = 0, tried = 0;
        for (uint32_t f = 0; f < F_; ++f) {
            const auto& fd = frames_[f];
            for (std::size_t i = 0; i < fd.landmark_points.size(); ++i, ++nl)
                lm2 += (kin_[f].point(fd.landmark_points[i]) - fd.landmark_targets[i]).squaredNorm();
            for (const auto& p : fd.pairs) {
                if (!p.model.weight[1]) {
                    pd += (kin_[f].point(p.model) - p.target).norm();
                    ++np;
                }
            }
            accepted += fd.pairs.size();
            tried += pair_candidates_[f];
        }
        for (uint32_t f = 0; f < F_; ++f) sol.report.unexplained = std::max(sol.report.unexplained, unexplained_share(f));
        update_kinematics();
        sol.report.iterations = iteration;
        // A fit that leaves this much of a scan unexplained has not found the person: not converged.
        sol.report.converged = converged && sol.report.unexplained <= kFailedUnexplained;
        sol.report.implausible = implausible_;
        sol.report.cancelled = cancelled;
        sol.report.landmark_rms = nl ? std::sqrt(lm2 / double(nl)) : 0;
        sol.report.point_mean = np ? pd / double(np) : 0;
        sol.report.inlier_fraction = tried ? double(accepted) / double(tried) : 0;
        sol.shape = shape_;
        sol.frames = states_;
        for (auto& s : sol.frames) s.shape = shape_;
        sol.report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return sol;
    }

private:
    // The coarse-to-fine stages from stages[first_stage] on, with the limb search between the coarse
    // and the fine stage. Returns whether the fine stage converged.
    bool fit_stages(const Stage (&stages)[4], int first_stage, const FitProgress& progress, uint32_t& iteration, bool& cancelled,
                    double* first_cost) {
        bool converged = false;
        for (int si = first_stage; si < 4 && !cancelled; ++si) {
            if (stages[si].iterations == 0) continue;
            // The polish has a fixed budget: convergence is the fine stage's.
            const bool stage_converged = run_stage(stages[si], kAllFrames, &progress, iteration, cancelled, first_cost);
            if (si < 3) converged = stage_converged;
            // After the fine stage, with the wrists in place: how closed each hand is, and when a
            // hand changed, the fine stage again from there.
            if (si == 2 && o_.hand_search && !cancelled && search_hands()) {
                Stage again = stages[2];
                again.iterations = std::max<uint32_t>(2, again.iterations / 2);
                converged = run_stage(again, kAllFrames, &progress, iteration, cancelled);
            }
            // Between the coarse and the fine stage: limbs the coarse stage could not reach, each
            // search settled by a short coarse stage when a limb moved. Limbs are searched one after
            // another, so a limb that gained kResweep of the measure (a raised leg found) changed
            // what the limbs searched before it had to explain: they are searched again.
            if (si == 1 && !cancelled) {
                Stage again = stages[1];
                again.iterations = std::max<uint32_t>(1, stages[1].iterations / 2);
                std::size_t count = kLimbCount;
                for (int sweep = 0; sweep < 2 && count > 0 && !cancelled; ++sweep) {
                    const LimbGains gains = search_limbs(count);
                    if (*std::max_element(gains.begin(), gains.end()) > 0) run_stage(again, kAllFrames, &progress, iteration, cancelled);
                    const std::size_t searched = count;
                    count = 0;  // the limbs before the last that gained kResweep
                    for (std::size_t i = 0; i < searched; ++i)
                        if (gains[i] >= kResweep) count = i;
                }
            }
        }
        return converged;
    }

    // A single frame's fit from the automatic start that ends implausible (joints far past their
    // limits: a body forced onto data of the other way round) or leaves more than
    // kRetryUnexplained of its scan unexplained (a limb or the body in the wrong place) is redone from the start search's
    // other candidates, best first, until one ends plausible (kMaxRestarts). The kept fit is the
    // first plausible one, else the one explaining the cloud best; a cancelled restart keeps the
    // fits before it. Restarts are rare (2 of 670 benchmark fits, each then fixed: 545 and 541 mm
    // mean vertex error to 1.6 and 1.1) and each costs a fit. Returns whether the kept fit converged.
    bool restart_if_implausible(const Stage (&stages)[4], const FitProgress& progress, uint32_t& iteration, bool& cancelled,
                                uint32_t& restarts, bool converged) {
        update_kinematics();
        const double prior = pose_priors(0, nullptr, nullptr), unexplained = unexplained_share(0);
        auto acceptable = [](double p, double u) { return p <= kImplausibleFit && u <= kRetryUnexplained; };
        if (acceptable(prior, unexplained)) return converged;
        struct Attempt {
            std::vector<double> shape;
            std::vector<FitState> states;
            bool converged;
            double prior, unexplained, measure;
        };
        Attempt best{shape_, states_, converged, prior, unexplained, explained(0)};
        // The start poses not tried yet get their short fits now; all candidates, best first.
        std::vector<std::pair<double, FitState>> alternatives = alternative_starts_;
        double best_cost = std::numeric_limits<double>::infinity(), best_prior = 0;
        for (const auto& [t, found] : deferred_templates_) {
            best_prior = 0;
            short_fits(0, found, &start_templates()[t].pose, alternatives, best_cost, best_prior);
        }
        std::stable_sort(alternatives.begin(), alternatives.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        for (const auto& [cost, alternative] : alternatives) {
            if (acceptable(best.prior, best.unexplained) || restarts == kMaxRestarts) break;
            states_[0] = alternative;
            shape_ = alternative.shape;
            const bool c = fit_stages(stages, 1, progress, iteration, cancelled, nullptr);
            if (cancelled) break;
            ++restarts;
            update_kinematics();
            const double p = pose_priors(0, nullptr, nullptr), u = unexplained_share(0), measure = explained(0);
            if (acceptable(p, u) || measure < best.measure) best = {shape_, states_, c, p, u, measure};
        }
        shape_ = best.shape;
        states_ = best.states;
        update_kinematics();
        // Still implausible after the restarts: most likely a limb or the body in the wrong place
        // (benchmark poses crouching and bent over), reported as failed.
        implausible_ = !cancelled && !acceptable(best.prior, best.unexplained);
        return best.converged && !implausible_;
    }

    // Model vertices for the model-to-scan direction, drawn by surface area (uniform over the
    // surface, as scans are), so the finely meshed hands and face are not oversampled.
    void sample_vertices(std::mt19937& rng) {
        const auto& d = lin_.model.data();
        const FitOptions& o = o_;
        const LinearModel& lin = lin_;
        std::vector<double> area(lin.V, 0.0);
        const auto& tri = d.mesh.triangles;
        auto mean = [&](uint32_t v) { return Vector3d(d.shape.mean[3 * v], d.shape.mean[3 * v + 1], d.shape.mean[3 * v + 2]); };
        for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
            const double a = 0.5 * (mean(tri[t + 1]) - mean(tri[t])).cross(mean(tri[t + 2]) - mean(tri[t])).norm();
            for (int i = 0; i < 3; ++i) area[tri[t + i]] += a / 3;
        }
        std::discrete_distribution<uint32_t> pick(area.begin(), area.end());
        std::vector<uint8_t> taken(lin.V, 0);
        for (uint32_t n = 0; n < 4 * o.max_points && vertex_sample_.size() < o.max_points; ++n) {
            const uint32_t v = pick(rng);
            if (!taken[v]) taken[v] = 1, vertex_sample_.push_back(v);
        }
    }

    // Levenberg-Marquardt iterations of one stage (all frames, or one). Returns whether it converged.
    bool run_stage(const Stage& st, uint32_t frame_only, const FitProgress* progress, uint32_t& iteration, bool& cancelled,
                   double* first_cost = nullptr) {
        double mu = kInitialDamping;
        // Correspondences are found again every iteration, so the cost keeps moving by a little
        // even at the solution: a stage also ends when st.stall iterations in a row fail to beat
        // its best cost by a fraction kPlateau.
        double best_cost = std::numeric_limits<double>::infinity();
        uint32_t stalled = 0;
        for (uint32_t it = 0; it < st.iterations; ++it, ++iteration) {
            update_kinematics();
            find_pairs(st, frame_only);
            ArrowSystem H;
            VectorXd g;
            const double cost = evaluate(st, &H, &g, frame_only);
            if (first_cost && iteration == 0) *first_cost = cost;
            if (progress && *progress && !(*progress)(iteration, cost)) {
                cancelled = true;
                return false;
            }
            const std::vector<int> cols = solve_columns(st);
            // Damp until the cost (same correspondences) goes down.
            const std::vector<double> shape0 = shape_;
            const std::vector<FitState> states0 = states_;
            bool improved = false;
            double new_cost = cost;
            for (int attempt = 0; attempt < kDampedAttempts && !improved; ++attempt) {
                const VectorXd delta = H.damped_solve(g, cols, mu, *pool_);
                if (!delta.allFinite()) {
                    mu *= kDampingUp;
                    continue;
                }
                apply(delta);
                update_kinematics(false);
                new_cost = evaluate(st, nullptr, nullptr, frame_only);
                if (new_cost < cost) {
                    improved = true;
                    mu = std::max(mu / kDampingDown, kMinDamping);
                } else {
                    shape_ = shape0;
                    states_ = states0;
                    mu *= kDampingUp;
                }
            }
            if (!improved || cost - new_cost < st.tolerance * std::max(cost, 1e-12)) {
                ++iteration;
                return true;
            }
            if (new_cost < best_cost * (1 - kPlateau)) {
                best_cost = new_cost;
                stalled = 0;
            } else if (++stalled >= st.stall) {
                ++iteration;
                return true;
            }
        }
        return false;
    }

    // Normals the input did not give (zero) estimated from the neighbouring points.
    void estimate_missing_normals(FrameData& fd) {
        bool missing = false;
        for (const auto& n : fd.normals) missing = missing || n.squaredNorm() == 0;
        if (!missing) return;
        build_scan_tree(fd);
        fd.oriented = fitting::estimate_missing_normals(fd.points, *fd.scan_index, fd.normals);
    }

    // The start search's grid over a frame's cloud (CloudView::coarse_grid).
    void build_start_grid(FrameData& fd) {
        fd.start_grid.build(fd.points);
        fd.start_grid.index_empty_space(kStartShells, *pool_);
    }

    // The k-d tree over a frame's cloud, for normal estimation's k-nearest queries.
    static void build_scan_tree(FrameData& fd) {
        if (!fd.scan_index) fd.scan_index = std::make_unique<PointIndex>(fd.points);
    }

    // The start: rigid alignment (with scale when fitted) of the mean body.
    // The template placed by a similarity (world = scale R u + t for its points u), in `pose`
    // (default the rest pose): a root rotation about the root joint (so the pose carries it) plus
    // translation.
    FitState placed(uint32_t f, const Similarity& T, const std::vector<Quaterniond>* pose = nullptr) {
        FitState s = kin_[f].zero_state();
        kin_[f].update(s);
        const Vector3d root = kin_[f].joint_position(0);
        if (pose) s.pose = *pose;
        const Matrix3d R0 = lin_.rest_orient[0];
        s.pose[0] = (Quaterniond(R0.transpose() * T.R * R0) * s.pose[0]).normalized();
        s.scale = T.scale;
        s.translation = T.t + T.scale * T.R * root - T.scale * root;
        return s;
    }

    // Short coarse fits (pose and the main shape components) of a template's rigid candidates,
    // best first: the two best, more while the best so far ends implausible (at most
    // kMaxShortFits). Each result joins `checked` with its explained measure.
    void short_fits(uint32_t f, const std::vector<StartCandidate>& found, const std::vector<Quaterniond>* pose,
                    std::vector<std::pair<double, FitState>>& checked, double& best_cost, double& best_prior) {
        const Stage coarse{8, true, false, std::min<uint32_t>(K_, 10), 0.15, 8.0, 0.0, 0.25};
        for (std::size_t i = 0; i < found.size(); ++i) {
            if ((i >= 2 && best_prior <= kImplausiblePose) || i >= kMaxShortFits) break;
            std::fill(shape_.begin(), shape_.end(), 0.0);
            states_[f] = placed(f, found[i].placement, pose);
            uint32_t iterations = 0;
            bool cancelled = false;
            run_stage(coarse, f, nullptr, iterations, cancelled);
            update_kinematics();
            find_pairs(coarse, f);
            const double cost = explained(f);
            checked.emplace_back(cost, states_[f]);
            if (cost < best_cost) best_cost = cost, best_prior = pose_priors(f, nullptr, nullptr);
        }
    }

    FitState initial_state(uint32_t f) {
        const auto& fd = frames_[f];
        if (fd.landmark_points.size() >= 3) {
            FitState s = kin_[f].zero_state();
            kin_[f].update(s);
            Eigen::Matrix3Xd src(3, fd.landmark_points.size()), dst(3, fd.landmark_points.size());
            for (std::size_t i = 0; i < fd.landmark_points.size(); ++i) {
                src.col(Eigen::Index(i)) = kin_[f].point(fd.landmark_points[i]);
                dst.col(Eigen::Index(i)) = fd.landmark_targets[i];
            }
            return placed(f, align_points(src, dst, o_.fit_scale));
        }
        // No landmarks: the rigid start search (rigid_start.hpp) over the mean body at rest.
        RigidStartOptions ro;
        ro.fit_scale = o_.fit_scale;
        ro.point_sigma = o_.point_sigma;
        ro.points = std::size_t(0.15 * o_.max_points);
        ro.samples = kExplainedSamples;
        build_start_grid(frames_[f]);
        // The rigid measure tells front from back far worse than a short coarse fit does: the best
        // candidates get one (short_fits). (One scan of 390 had its right heading ranked last by
        // the rigid measure.)
        ++searched_frames_;
        double best_cost = std::numeric_limits<double>::infinity(), best_prior = 0;
        std::vector<std::pair<double, FitState>> checked;  // explained measure after the short fit, state
        const std::vector<StartCandidate> at_rest = rigid_start(rest_sample(), cloud_view(fd), ro, *pool_);
        short_fits(f, at_rest, nullptr, checked, best_cost, best_prior);
        // A crouching, seated or bent-over person has other principal axes than a standing body:
        // the template in each start pose (kStartPoses) is placed too (half the rigid steps and
        // correspondences: it only has to show it explains the scan better). Its candidates get
        // short fits now when it explains the scan better than the rest pose after rigid
        // placement, or when the rest pose's fits all ended implausible; else only if the fit
        // fails and is restarted (restart_if_implausible()).
        RigidStartOptions quick = ro;
        quick.steps = ro.steps / 2;
        quick.points = ro.points / 2;
        deferred_templates_.clear();
        for (std::size_t t = 0; t < start_templates().size(); ++t) {
            std::vector<StartCandidate> posed = rigid_start(start_templates()[t].sample(), cloud_view(fd), quick, *pool_);
            if (posed.front().score >= at_rest.front().score && best_prior <= kImplausiblePose) {
                if (F_ == 1) deferred_templates_.emplace_back(t, std::move(posed));
                continue;
            }
            const double prior = best_prior;
            best_prior = 0;  // the template's best two at least
            short_fits(f, posed, &start_templates()[t].pose, checked, best_cost, best_prior);
            best_prior = std::min(best_prior, prior);
        }
        // Best first (the first of equals): the start, then the others for restarts (run()).
        std::stable_sort(checked.begin(), checked.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        if (F_ == 1) alternative_starts_.assign(checked.begin() + 1, checked.end());
        std::fill(shape_.begin(), shape_.end(), 0.0);
        return checked.front().second;
    }

    // Arms and legs the coarse stage cannot reach (limb_search.hpp): the first `count` limbs, for
    // every frame with a cloud. Returns each limb's largest relative gain over the frames.
    LimbGains search_limbs(std::size_t count) {
        LimbGains gains{};
        for (uint32_t f = 0; f < F_; ++f)
            if (!frames_[f].points.empty()) {
                const LimbGains g = fitting::search_limbs(kin_[f], body_, states_[f], cloud_view(frames_[f]), vertex_sample_, *pool_, count);
                for (std::size_t i = 0; i < kLimbCount; ++i) gains[i] = std::max(gains[i], g[i]);
            }
        update_kinematics();
        return gains;
    }

    // How closed each hand is (hand_search.hpp), for every frame with a cloud.
    // Returns whether a hand changed.
    bool search_hands() {
        bool changed = false;
        for (uint32_t f = 0; f < F_; ++f)
            if (!frames_[f].points.empty()) {
                const double before[2] = {states_[f].hand_closure[0], states_[f].hand_closure[1]};
                fitting::search_hands(kin_[f], body_, states_[f], cloud_view(frames_[f]), vertex_sample_);
                changed |= before[0] != states_[f].hand_closure[0] || before[1] != states_[f].hand_closure[1];
            }
        update_kinematics();
        return changed;
    }

    // The vertex sample on the mean body at rest, for the rigid start search; built on first use.
    // The template (mean shape) in a start pose: the vertex sample posed, its principal frame.
    struct StartTemplate {
        std::vector<Quaterniond> pose;
        std::vector<Vector3d> points, normals;
        std::unique_ptr<PointIndex> index;
        Vector3d centre = Vector3d::Zero();
        double bottom = 0, top = 0;
        Matrix3d frame = Matrix3d::Identity();
        RestSample sample() const {
            RestSample r;
            r.points = &points, r.normals = &normals, r.index = index.get();
            r.centre = centre, r.bottom = bottom, r.top = top, r.frame = frame;
            return r;
        }
    };
    const std::vector<StartTemplate>& start_templates() {
        if (!start_templates_.empty() || !lin_.model.data().joint_limits.size()) return start_templates_;
        // In place: a PointIndex refers to its points vector, so templates never move once built.
        start_templates_.reserve(std::size(kStartPoses));
        for (const char* name : kStartPoses) {
            StartTemplate& t = start_templates_.emplace_back();
            const std::vector<float> q = anatomy::named_pose(lin_.model, name, &lin_.limits);
            for (uint32_t j = 0; j < lin_.J; ++j) t.pose.emplace_back(q[4 * j + 3], q[4 * j], q[4 * j + 1], q[4 * j + 2]);
            FitState st = kin_[0].zero_state();
            st.pose = t.pose;
            posed_surface(body_, st, posed_, &posed_normals_);
            for (uint32_t v : vertex_sample_) t.points.push_back(posed_[v]), t.normals.push_back(posed_normals_[v]);
            t.index = std::make_unique<PointIndex>(t.points);
            Matrix3d cov = Matrix3d::Zero();
            for (uint32_t v = 0; v < lin_.V; v += 7) t.centre += posed_[v];
            t.centre /= double((lin_.V + 6) / 7);
            for (uint32_t v = 0; v < lin_.V; v += 7) cov += (posed_[v] - t.centre) * (posed_[v] - t.centre).transpose();
            const Eigen::SelfAdjointEigenSolver<Matrix3d> es(cov);
            const Vector3d up = es.eigenvectors().col(2), second = es.eigenvectors().col(1);
            t.frame.col(1) = up;
            t.frame.col(2) = second;
            t.frame.col(0) = up.cross(second);
            t.bottom = 1e9, t.top = -1e9;
            for (uint32_t v = 0; v < lin_.V; v += 7) {
                const double h = (posed_[v] - t.centre).dot(up);
                t.bottom = std::min(t.bottom, h), t.top = std::max(t.top, h);
            }
            t.bottom += t.centre.dot(up), t.top += t.centre.dot(up);
        }
        return start_templates_;
    }

    RestSample rest_sample() {
        RestSample r;
        if (!rest_index_) {
            const FitState zero = kin_[0].zero_state();
            posed_surface(body_, zero, posed_, &posed_normals_);
            for (uint32_t v : vertex_sample_) rest_points_.push_back(posed_[v]), rest_normals_.push_back(posed_normals_[v]);
            rest_index_ = std::make_unique<PointIndex>(rest_points_);
            // Centre and height of the whole surface, every 7th vertex.
            rest_centre_.setZero();
            rest_bottom_ = 1e9, rest_top_ = -1e9;
            for (uint32_t v = 0; v < lin_.V; v += 7) {
                rest_centre_ += posed_[v];
                rest_bottom_ = std::min(rest_bottom_, posed_[v].y()), rest_top_ = std::max(rest_top_, posed_[v].y());
            }
            rest_centre_ /= double((lin_.V + 6) / 7);
        }
        r.centre = rest_centre_;
        r.bottom = rest_bottom_;
        r.top = rest_top_;
        r.points = &rest_points_;
        r.normals = &rest_normals_;
        r.index = rest_index_.get();
        return r;
    }

    CloudView cloud_view(const FrameData& fd) const {
        CloudView c;
        c.confidence = &fd.confidence;
        c.points = &fd.points;
        c.normals = &fd.normals;
        c.oriented = fd.oriented;
        c.grid = &fd.scan_grid;
        c.coarse_grid = &fd.start_grid;
        c.sample = &fd.scan_sample;
        return c;
    }

    // The share of frame f's scan sample (its first kExplainedSamples points) farther than
    // kUnexplainedDistance from the posed model and on a surface (kSurfaceNeighbours within
    // kSurfaceRadius): data the fit does not explain (a limb in the wrong place, a body turned
    // over). Isolated points (outliers, sparse clutter) do not count. 0 for a frame without points.
    double unexplained_share(uint32_t f) {
        auto& fd = frames_[f];
        if (fd.points.empty()) return 0;
        kin_[f].update(states_[f], false);
        pose_frame(f, false);
        sample_grid_.build(posed_subset());
        const std::size_t n = std::min(kExplainedSamples, fd.scan_sample.size());
        std::size_t far = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const Vector3d& p = fd.points[fd.scan_sample[i]];
            if (sample_grid_.nearest(p, kUnexplainedDistance, nullptr) != GridIndex::kNone) continue;
            build_scan_tree(fd);
            uint32_t index[kSurfaceNeighbours + 1];
            double d2[kSurfaceNeighbours + 1];
            const std::size_t found = fd.scan_index->nearest_k(p, kSurfaceNeighbours + 1, index, d2);  // itself among them
            far += found == kSurfaceNeighbours + 1 && d2[kSurfaceNeighbours] <= kSurfaceRadius * kSurfaceRadius;
        }
        return double(far) / double(n);
    }

    // The posed positions of the area-sampled vertex subset (posed_ must be current).
    const std::vector<Vector3d>& posed_subset() {
        subset_posed_.resize(vertex_sample_.size());
        for (std::size_t i = 0; i < vertex_sample_.size(); ++i) subset_posed_[i] = posed_[vertex_sample_[i]];
        return subset_posed_;
    }

    // How badly the current state of frame f explains its cloud, for choosing between start
    // candidates: truncated squared distances both ways over fixed point sets, a point whose
    // nearest partner faces the other way counting as unexplained. Unlike the fit's cost (which
    // gates correspondences away), a candidate cannot look good by leaving data unexplained.
    double explained(uint32_t f) {
        kin_[f].update(states_[f], false);
        pose_frame(f, false);
        sample_grid_.build(posed_subset());
        subset_normals_.resize(vertex_sample_.size());
        for (std::size_t i = 0; i < vertex_sample_.size(); ++i) subset_normals_[i] = posed_normals_[vertex_sample_[i]];
        return explained_measure(
            cloud_view(frames_[f]), subset_posed_, subset_normals_,
            [&](const Vector3d& p) { return sample_grid_.nearest(p, kPlacementCap, nullptr); }, kPlacementCap, kExplainedSamples);
    }

    // derivatives = false for cost-only evaluations (the trial steps), which need no Jacobians.
    void update_kinematics(bool derivatives = true) {
        for (uint32_t f = 0; f < F_; ++f) {
            states_[f].shape = shape_;
            kin_[f].update(states_[f], derivatives);
        }
    }

    // Posed vertices and normals of frame f: every vertex (the synthesis kernels), or only the
    // vertex sample, posed by kin_[f] (which must be current) with its rest normals carried by the
    // skinning rotation. The sample is a quarter of the vertices and needs no normals pass: enough
    // for the coarse stages and the explained measure, which use the sample only.
    void pose_frame(uint32_t f, bool every_vertex) {
        if (every_vertex) {
            posed_surface(body_, states_[f], posed_, &posed_normals_);
            return;
        }
        rest_sample();  // the rest normals (built on first use)
        const Kinematics& kin = kin_[f];
        constexpr std::size_t kChunks = 8;
        const std::size_t n = vertex_sample_.size();
        pool_->parallel_for(kChunks, [&](std::size_t c, unsigned) {
            for (std::size_t s = c * n / kChunks; s < (c + 1) * n / kChunks; ++s) {
                const uint32_t v = vertex_sample_[s];
                posed_[v] = kin.posed_vertex(v, kin.rest_vertex(v));
                posed_normals_[v] = (kin.skin_rotation(v) * rest_normals_[s]).normalized();
            }
        });
    }

    void find_pairs(const Stage& st, uint32_t frame_only = kAllFrames) {
        pair_candidates_.assign(F_, 0);
        for (uint32_t f = 0; f < F_; ++f) {
            if (frames_[f].points.empty() || (frame_only < F_ && f != frame_only)) continue;
            pose_frame(f, st.dense_model);
            find_frame_pairs(f, st);
        }
    }

    // Correspondences both ways with compatibility tests and trimming (posed_ must be frame f's).
    void find_frame_pairs(uint32_t f, const Stage& st) {
        auto& fd = frames_[f];
        fd.pairs.clear();
        ++pairs_version_;
        if (fd.points.empty()) return;
        if (pair_candidates_.size() < F_) pair_candidates_.assign(F_, 0);
        // Model points for scan-to-model queries: all vertices or the subset (see Stage).
        GridIndex& model_index = st.dense_model ? dense_grid_ : sample_grid_;
        model_index.build(st.dense_model ? posed_ : posed_subset());
        const std::size_t n_scan = std::max<std::size_t>(
            16, std::min<std::size_t>(fd.scan_sample.size(), std::size_t(st.point_fraction * o_.max_points)));
        const std::size_t n_model = std::max<std::size_t>(16, std::min<std::size_t>(vertex_sample_.size(), n_scan));
        const double max2 = st.max_distance * st.max_distance;
        auto compatible = [&](const Vector3d& scan_n, const Vector3d& model_n) {
            return normals_agree(scan_n, model_n, fd.oriented, st.min_normal_dot);
        };
        using Found = std::vector<std::pair<double, Pair>>;
        // Both directions' queries run in one batch on the pool's threads, in fixed chunks merged
        // in order, and each direction is trimmed on its own (one thread each): the same pairs
        // for any thread count.
        constexpr std::size_t kChunks = 8;
        Found chunks[2][kChunks];
        auto scan_to_model = [&](std::size_t s, Found& out) {
            const uint32_t i = fd.scan_sample[s];
            double d2;
            const uint32_t nearest = model_index.nearest(fd.points[i], st.max_distance, &d2);
            if (nearest == GridIndex::kNone) return;
            const uint32_t v = st.dense_model ? nearest : vertex_sample_[nearest];
            if (!compatible(fd.normals[i], posed_normals_[v]) || fd.confidence[i] <= 0) return;
            Pair p;
            p.model.vertex[0] = v;
            p.target = fd.points[i];
            p.normal = posed_normals_[v];  // the model's normal: always known and oriented
            p.weight = fd.confidence[i];
            out.emplace_back(d2, p);
        };
        auto model_to_scan = [&](std::size_t s, Found& out) {
            const uint32_t v = vertex_sample_[s];
            double d2;
            const uint32_t i = fd.scan_grid.nearest(posed_[v], st.max_distance, &d2);
            if (i == GridIndex::kNone || !compatible(fd.normals[i], posed_normals_[v]) || fd.confidence[i] <= 0) return;
            // Holes: a model vertex over a hole in the scan finds the nearest point at the hole's
            // edge, which belongs to another part of the model and would drag this part onto it
            // (a hand in a hole curls onto the wrist). Such a point's own nearest model point is
            // far from the vertex: the pair is kept only if the two agree to within a fraction of
            // the gate. (Both lie within the pair's distance of the scan point, so pairs closer
            // than half that fraction pass without the query.)
            const double agree2 = kReciprocal * kReciprocal * max2;
            if (4 * d2 > agree2) {
                const uint32_t back = model_index.nearest(fd.points[i], st.max_distance, nullptr);
                if (back == GridIndex::kNone || (posed_[st.dense_model ? back : vertex_sample_[back]] - posed_[v]).squaredNorm() > agree2) return;
            }
            Pair p;
            p.model.vertex[0] = v;
            p.target = fd.points[i];
            p.normal = fd.normals[i].squaredNorm() > 0 ? fd.normals[i] : posed_normals_[v];
            p.weight = 0.5 * fd.confidence[i];  // the two directions share one budget
            out.emplace_back(d2, p);
        };
        const std::size_t count[2] = {n_scan, n_model};
        pool_->parallel_for(2 * kChunks, [&](std::size_t item, unsigned) {
            const std::size_t d = item / kChunks, c = item % kChunks;
            for (std::size_t s = c * count[d] / kChunks; s < (c + 1) * count[d] / kChunks; ++s)
                d == 0 ? scan_to_model(s, chunks[d][c]) : model_to_scan(s, chunks[d][c]);
        });
        pair_candidates_[f] += n_scan + n_model;
        std::vector<Pair> kept[2];
        pool_->parallel_for(2, [&](std::size_t d, unsigned) {
            Found found;
            for (const Found& c : chunks[d]) found.insert(found.end(), c.begin(), c.end());
            std::vector<double> scratch;
            append_trimmed(found, scratch, kept[d]);
        });
        fd.pairs.insert(fd.pairs.end(), kept[0].begin(), kept[0].end());
        fd.pairs.insert(fd.pairs.end(), kept[1].begin(), kept[1].end());
    }

    // The column set of a block's Jacobian (active columns only), cached per frame and vertex
    // for single-vertex points.
    uint32_t column_set(const Block& b) {
        const bool single = b.point->weight[1] == 0 && b.point->weight[2] == 0;
        uint32_t& cached = vertex_set_[b.frame][b.point->vertex[0]];
        if (single && cached != kNoSet) return cached;
        kin_[b.frame].nonzeros(*b.point, nonzeros_);
        set_columns_.clear();
        for (uint32_t c : nonzeros_)
            if (set_active_[c]) set_columns_.push_back(column(b.frame, c));
        const uint32_t set = normal_.column_set(set_columns_);
        if (single) cached = set;
        return set;
    }

    // Global column of a frame-local parameter.
    uint32_t column(uint32_t f, uint32_t local) const { return local < K_ ? local : K_ + f * B_ + (local - K_); }

    bool active(const Stage& st, uint32_t local) const {
        if (local < K_) return local < st.components;
        const uint32_t r = local - K_;
        if (r >= 3 * lin_.J) return r < 3 * lin_.J + 3 || o_.fit_scale;  // translation, scale
        const uint32_t j = r / 3;
        if (j == 0) return true;  // the root carries the global rotation
        if (st.all_joints) return true;
        // Coarse stages move the trunk and limbs, not the wrists (nor fingers and toes): their far-
        // reaching correspondences bent a hand over a hole in the scan onto the forearm's points,
        // and the fine stage could not bend it back (anatomy/joint_roles.hpp).
        return st.body_joints && coarse_joint_[j] != 0;
    }

    // The columns a step solves for: active in the stage and, for joint rotations and frame
    // parameters, touched by some data row in the last evaluate(). Joints nothing observes (the
    // fingers, for landmarks) keep their value; leaving them out shrinks the system severalfold.
    std::vector<int> solve_columns(const Stage& st) const {
        std::vector<int> cols;
        for (uint32_t f = 0; f < F_; ++f)
            for (uint32_t local = 0; local < K_ + B_; ++local) {
                if (f > 0 && local < K_) continue;
                const uint32_t c = column(f, local);
                if (active(st, local) && (local < K_ || touched_[c])) cols.push_back(int(c));
            }
        return cols;
    }

    void apply(const VectorXd& delta) {
        // Box constraint: the shape stays where the C API accepts it back (shape_range.hpp).
        for (uint32_t k = 0; k < K_; ++k) shape_[k] = within_shape_range(shape_[k] + delta[k]);
        std::vector<double> local(K_ + B_, 0.0);
        for (uint32_t f = 0; f < F_; ++f) {
            for (uint32_t i = 0; i < B_; ++i) local[K_ + i] = delta[K_ + f * B_ + i];
            kin_[f].apply(local.data(), states_[f]);
        }
    }

    // The pose prior and the joint-limit walls of frame f; with H and g, their normal equations.
    double pose_priors(uint32_t f, ArrowSystem* H, VectorXd* g) const {
        double cost = 0;
        const Kinematics& kin = kin_[f];
        // Pose prior: each joint's local rotation vector, over its sigma (not the root: free).
        for (uint32_t j = 1; j < lin_.J; ++j) {
            const double s = std::sqrt(o_.pose_prior) / joint_sigma_[j];
            if (s == 0) continue;
            const Vector3d r = log_rotation(states_[f].pose[j]);
            // Centred on the rest pose, the fingers on their hand's closure.
            const Vector3d centre = hand_of_joint_[j] < 0 ? Vector3d(Vector3d::Zero()) : Vector3d(states_[f].hand_closure[hand_of_joint_[j]] * closed_fingers_[j]);
            cost += 0.5 * s * s * (r - centre).squaredNorm();
            if (!H) continue;
            const Matrix3d Jr = s * inverse_left_jacobian(r) * kin.local_from_world(j);
            const uint32_t c0 = column(f, kin.rotation_offset(j));
            const Matrix3d JtJ = Jr.transpose() * Jr;
            const Vector3d Jtr = Jr.transpose() * (s * (r - centre));
            for (int a = 0; a < 3; ++a) {
                (*g)[c0 + a] += Jtr[a];
                for (int b = a; b < 3; ++b) H->add(c0 + a, c0 + b, JtJ(a, b));
            }
        }
        // Joint limits: a quadratic wall per anatomical component beyond its range.
        for (uint32_t j = 1; j < lin_.J && !limits_.empty(); ++j) {
            const anatomy::JointLimit& lim = limits_[j];
            if (!lim.limited) continue;
            const Vector3d r = log_rotation(states_[f].pose[j]);
            const Vector3d c = lim.to_anatomical * r;
            Vector3d e = Vector3d::Zero();
            for (int a = 0; a < 3; ++a) {
                if (c[a] > lim.hi[a]) e[a] = (c[a] - lim.hi[a]) / kLimitSigma;
                else if (c[a] < lim.lo[a]) e[a] = (c[a] - lim.lo[a]) / kLimitSigma;
            }
            if (e.isZero()) continue;
            cost += 0.5 * e.squaredNorm();
            if (!H) continue;
            // Rows of the active components only: d c / d w = M J_l^-1(r) A^T, over the sigma.
            Matrix3d Jc = lim.to_anatomical * inverse_left_jacobian(r) * kin.local_from_world(j) / kLimitSigma;
            for (int a = 0; a < 3; ++a)
                if (e[a] == 0) Jc.row(a).setZero();
            const uint32_t c0 = column(f, kin.rotation_offset(j));
            const Matrix3d JtJ = Jc.transpose() * Jc;
            const Vector3d Jte = Jc.transpose() * e;
            for (int a = 0; a < 3; ++a) {
                (*g)[c0 + a] += Jte[a];
                for (int b = a; b < 3; ++b) H->add(c0 + a, c0 + b, JtJ(a, b));
            }
        }
        return cost;
    }

    // Cost of the current state with the current correspondences; with H and g, the normal
    // equations of its linearisation. frame_only < F_ restricts the data to one frame.
    double evaluate(const Stage& st, ArrowSystem* H, VectorXd* g, uint32_t frame_only = kAllFrames) {
        const uint32_t P = parameters();
        const uint32_t PL = K_ + B_;
        // Only active parameters get rows: the rigid and coarse stages cost a fraction of the full one.
        std::vector<uint8_t> on(PL);
        for (uint32_t i = 0; i < PL; ++i) on[i] = active(st, i);
        if (on != set_active_) {  // column sets follow the active parameters
            normal_.clear();
            set_active_ = on;
            vertex_set_.assign(F_, std::vector<uint32_t>(lin_.V, kNoSet));
        }
        // The blocks follow the correspondences: the trial steps of an iteration reuse its blocks.
        if (blocks_pairs_ != pairs_version_ || blocks_frame_ != frame_only) {
            blocks_.clear();
            for (uint32_t f = 0; f < F_; ++f) {
                if (frame_only < F_ && f != frame_only) continue;
                const auto& fd = frames_[f];
                for (std::size_t i = 0; i < fd.landmark_points.size(); ++i)
                    blocks_.push_back({f, &fd.landmark_points[i], &fd.landmark_targets[i], nullptr,
                                       std::sqrt(fd.landmark_weights[i]) / o_.landmark_sigma});
                for (const auto& p : fd.pairs) blocks_.push_back({f, &p.model, &p.target, &p.normal, std::sqrt(p.weight) / o_.point_sigma});
            }
            group_blocks();
            blocks_pairs_ = pairs_version_, blocks_frame_ = frame_only;
        }
        // The blocks run on the pool's threads in fixed chunks whose sums are merged in order:
        // the same result for any thread count.
        constexpr std::size_t kChunks = 8;
        double chunk_cost[kChunks] = {};
        if (H) {
            H->reset(K_, B_, F_);
            g->setZero(P);
            touched_.assign(P, 0);
            chunk_g_.assign(kChunks, VectorXd::Zero(P));
        }
        if (jacobian_scratch_.size() != pool_->size() || jacobian_scratch_[0].size() != 3 * std::size_t(PL))
            jacobian_scratch_.assign(pool_->size(), std::vector<double>(3 * std::size_t(PL), 0.0));
        // With H, the groups' rows are summed in batches of consecutive groups (kBatchDoubles of
        // rows each; groups follow the frames): a fit of many frames needs the memory of a few.
        for (std::size_t begin = 0, end = 0; begin < groups_.size(); begin = end) {
            end = groups_.size();
            if (H) {
                normal_.reset();
                std::size_t doubles = 0;
                for (end = begin; end < groups_.size() && doubles < kBatchDoubles; ++end) {
                    Group& gr = groups_[end];
                    gr.set = column_set(blocks_[members_[gr.first]]);
                    gr.row = normal_.reserve(gr.set, 3);
                    if (gr.row == 0)
                        for (uint32_t c : normal_.columns(gr.set)) touched_[c] = 1;
                    doubles += 3 * normal_.columns(gr.set).size();
                }
                normal_.allocate();
            }
            const std::size_t n_groups = end - begin;
            pool_->parallel_for(kChunks, [&](std::size_t c, unsigned worker) {
                double* J3 = jacobian_scratch_[worker].data();
                double sum = 0;
                for (std::size_t gi = begin + c * n_groups / kChunks; gi < begin + (c + 1) * n_groups / kChunks; ++gi) {
                    const Group& gr = groups_[gi];
                    const Block& first = blocks_[members_[gr.first]];
                    const Kinematics& kin = kin_[first.frame];
                    // With H the Jacobian (of the point) comes first: it computes the point on the way.
                    const Vector3d x = H ? kin.point_jacobian(*first.point, J3, on.data()) : kin.point(*first.point);
                    // Each term's Gauss-Newton weight on the point (s^2 L^T L, e = s (x - target)) and
                    // gradient factor (s m) add up over the group.
                    Matrix3d W = Matrix3d::Zero();
                    Vector3d m = Vector3d::Zero();
                    for (uint32_t k = gr.first; k < gr.first + gr.count; ++k) {
                        const Block& b = blocks_[members_[k]];
                        const Vector3d e = b.scale * (x - *b.target);
                        Matrix3d L;
                        Vector3d mb;
                        if (b.normal) {
                            const PointPlaneTerm term = point_plane(e, *b.normal, st.gm_scale, H != nullptr);
                            sum += term.cost;
                            L = term.L, mb = term.m;
                        } else {
                            const Robust rb = huber(e.norm(), kHuber);
                            sum += rb.cost;
                            L = std::sqrt(rb.weight) * Matrix3d::Identity(), mb = rb.weight * e;
                        }
                        if (!H) continue;
                        W.noalias() += (b.scale * b.scale) * (L.transpose() * L);
                        m += b.scale * mb;
                    }
                    if (!H) continue;
                    // Three rows R J with R^T R = W, on the group's column set, and J^T m into g.
                    const Matrix3d R = weight_root(W);
                    const std::vector<uint32_t>& cols = normal_.columns(gr.set);
                    const std::size_t n = cols.size();
                    double* rows = normal_.rows(gr.set, gr.row);
                    VectorXd& gc = chunk_g_[c];
                    for (std::size_t a = 0; a < n; ++a) {
                        const uint32_t l = cols[a] < K_ ? cols[a] : cols[a] - first.frame * B_;  // local column
                        const Vector3d j(J3[l], J3[PL + l], J3[2 * std::size_t(PL) + l]);
                        const Vector3d rj = R * j;
                        rows[a] = rj[0], rows[n + a] = rj[1], rows[2 * n + a] = rj[2];
                        gc[cols[a]] += j.dot(m);
                        J3[l] = J3[PL + l] = J3[2 * std::size_t(PL) + l] = 0;
                    }
                    // Translation and scale are written whether active or not.
                    for (uint32_t l = K_ + 3 * lin_.J; l < PL; ++l) J3[l] = J3[PL + l] = J3[2 * std::size_t(PL) + l] = 0;
                }
                chunk_cost[c] += sum;
            });
            if (H) normal_.add_to_upper(*H, *pool_);
        }
        double cost = 0;
        for (std::size_t c = 0; c < kChunks; ++c) {
            cost += chunk_cost[c];
            if (H) *g += chunk_g_[c];
        }
        for (uint32_t f = 0; f < F_; ++f)
            if (frame_only >= F_ || f == frame_only) cost += pose_priors(f, H, g);
        // Shape prior: the coefficients are standard deviations of the training population.
        for (uint32_t k = 0; k < K_; ++k) {
            cost += 0.5 * o_.shape_prior * shape_[k] * shape_[k];
            if (!H) continue;
            H->add(k, k, o_.shape_prior);
            (*g)[k] += o_.shape_prior * shape_[k];
        }
        return cost;
    }

    // Groups the blocks of evaluate(): the correspondences of one model vertex in one frame form
    // one group (a third of them share a vertex with another), every other block its own. A
    // group's Jacobian is computed once and its terms' weights add up into one 3-row block.
    // Groups follow their first block's order, members the blocks' order.
    void group_blocks() {
        groups_.clear();
        group_of_.resize(blocks_.size());
        if (vertex_group_.size() != std::size_t(F_) * lin_.V) vertex_group_.assign(std::size_t(F_) * lin_.V, kNoSet);
        for (std::size_t i = 0; i < blocks_.size(); ++i) {
            const Block& b = blocks_[i];
            const bool single = b.point->weight[1] == 0 && b.point->weight[2] == 0;
            uint32_t* slot = single ? &vertex_group_[std::size_t(b.frame) * lin_.V + b.point->vertex[0]] : nullptr;
            if (!slot || *slot == kNoSet) {
                if (slot) *slot = uint32_t(groups_.size());
                groups_.push_back({0, 0, 0, 0});
            }
            group_of_[i] = slot ? *slot : uint32_t(groups_.size() - 1);
            ++groups_[group_of_[i]].count;
        }
        uint32_t next = 0;
        for (Group& gr : groups_) gr.first = next, next += gr.count, gr.count = 0;
        members_.resize(blocks_.size());
        for (std::size_t i = 0; i < blocks_.size(); ++i) {
            Group& gr = groups_[group_of_[i]];
            members_[gr.first + gr.count++] = uint32_t(i);
        }
        for (const Block& b : blocks_)  // leave the map empty for the next call
            if (b.point->weight[1] == 0 && b.point->weight[2] == 0) vertex_group_[std::size_t(b.frame) * lin_.V + b.point->vertex[0]] = kNoSet;
    }

    // R with R^T R = W for a group's summed weight (symmetric positive definite: every term has
    // a point-to-point part): Cholesky, or the eigen-decomposition should rounding say otherwise.
    static Matrix3d weight_root(const Matrix3d& W) {
        const Eigen::LLT<Matrix3d> llt(W);
        if (llt.info() == Eigen::Success) return llt.matrixU();
        const Eigen::SelfAdjointEigenSolver<Matrix3d> es(W);
        return es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
    }

    const LinearModel& lin_;
    FitOptions o_;
    uint32_t F_, K_, B_;
    std::vector<FrameData> frames_;
    std::vector<Kinematics> kin_;
    std::vector<double> shape_;
    std::vector<FitState> states_;
    uint32_t searched_frames_ = 0;  // frames started by the cloud start search (with its coarse fit)
    // A single frame's other start candidates after their short fits, with the explained measure
    // (run()), and the start poses whose short fits were put off (initial_state()).
    std::vector<std::pair<double, FitState>> alternative_starts_;
    std::vector<std::pair<std::size_t, std::vector<StartCandidate>>> deferred_templates_;
    std::vector<uint32_t> vertex_sample_;
    std::vector<Vector3d> posed_, posed_normals_, subset_posed_, subset_normals_;
    std::vector<Vector3d> rest_points_, rest_normals_;  // see rest_sample()
    std::vector<StartTemplate> start_templates_;         // see start_templates()
    std::unique_ptr<PointIndex> rest_index_;
    // Over the posed model, rebuilt for each use: every vertex (spacing about 1 cm) or the sample
    // (about 2.5 cm).
    GridIndex dense_grid_{0.02}, sample_grid_{0.04};
    Vector3d rest_centre_ = Vector3d::Zero();
    double rest_bottom_ = 0, rest_top_ = 0;
    Body body_;
    ThreadPool inline_pool_{1};  // when the caller gives none
    ThreadPool* pool_;
    std::vector<std::size_t> pair_candidates_;
    std::vector<double> joint_sigma_;     // per joint: the rotation prior's sigma (joint_roles.hpp)
    std::vector<uint8_t> coarse_joint_;   // per joint: moved by the coarse stages
    bool implausible_ = false;  // restart_if_implausible found no acceptable fit
    std::vector<Vector3d> closed_fingers_;  // per joint: a finger's rotation vector at closure 1, else zero
    std::vector<int8_t> hand_of_joint_;     // per joint: 0 left hand's finger, 1 right, -1 neither
    std::vector<anatomy::JointLimit> limits_;  // empty when the options turn limits off
    NormalEquations normal_;  // data blocks of the H being built
    static constexpr uint32_t kNoSet = 0xFFFFFFFFu;
    std::vector<Block> blocks_;
    // Bumped whenever some frame's pairs change; blocks_ (and groups_) were made for this version
    // and frame selection.
    uint64_t pairs_version_ = 0, blocks_pairs_ = ~uint64_t(0);
    uint32_t blocks_frame_ = 0;
    struct Group {
        uint32_t first, count;  // its blocks: members_[first, first + count)
        uint32_t set;
        std::size_t row;
    };
    std::vector<Group> groups_;
    std::vector<uint32_t> members_, group_of_;  // group_blocks() output and scratch
    std::vector<uint32_t> vertex_group_;        // per frame and vertex: its group in the current call, or kNoSet
    std::vector<uint8_t> set_active_;                // the active local parameters the column sets were made for
    std::vector<std::vector<uint32_t>> vertex_set_;  // per frame and vertex: its column set, or kNoSet
    std::vector<uint32_t> nonzeros_, set_columns_;   // column_set() scratch
    std::vector<VectorXd> chunk_g_;                  // evaluate(): per chunk gradient
    std::vector<std::vector<double>> jacobian_scratch_;  // evaluate(): per worker, 3 rows of local columns, kept zero
    std::vector<uint8_t> touched_;  // columns some data row reached in the last evaluate() with H
};

void validate(const LinearModel& lin, const std::vector<Frame>& frames, const FitOptions& o) {
    const auto& d = lin.model.data();
    SSC_REQUIRE_ARG(!frames.empty(), "fit: no frames");
    SSC_REQUIRE_ARG(o.landmark_sigma > 0 && std::isfinite(o.landmark_sigma), "fit: landmark_sigma must be positive");
    SSC_REQUIRE_ARG(o.point_sigma > 0 && std::isfinite(o.point_sigma), "fit: point_sigma must be positive");
    SSC_REQUIRE_ARG(o.shape_prior >= 0 && std::isfinite(o.shape_prior), "fit: shape_prior must be >= 0");
    SSC_REQUIRE_ARG(o.pose_prior >= 0 && std::isfinite(o.pose_prior), "fit: pose_prior must be >= 0");
    SSC_REQUIRE_ARG(o.max_points >= 16, "fit: max_points must be at least 16");
    for (std::size_t f = 0; f < frames.size(); ++f) validate_frame(d, frames[f], "fit: frame " + std::to_string(f));
}

}  // namespace


bool is_hand_landmark(const std::string& name) {
    std::string lower;
    for (char c : name) lower += char(std::tolower(static_cast<unsigned char>(c)));
    return lower.find("metacarpal") != std::string::npos || lower.find("dactylion") != std::string::npos;
}

FitSolution fit(const LinearModel& lin, const std::vector<Frame>& frames, const FitOptions& options,
                const std::vector<FitState>* start, const FitProgress& progress, ThreadPool* pool) {
    validate(lin, frames, options);
    if (start && !options.auto_start)
        SSC_REQUIRE_ARG_S(start->size() == frames.size(), "fit: " << start->size() << " start states for " << frames.size() << " frames");
    // The reported time includes the setup (the scans' grids and k-d trees, normal estimation).
    const auto t0 = std::chrono::steady_clock::now();
    if (frames.size() == 1 || (start && !options.auto_start)) {
        Solver solver(lin, frames, options, pool);
        return solver.run(start, progress, t0);
    }
    // Several frames from the automatic start: each frame is first fitted alone, with everything a
    // single fit has (its start search, limb search and restarts), then all together from those
    // poses and the frames' median shape with the fine stages only (the shared shape's joint
    // refinement). The cost is about that of the single fits; fitted together from the start,
    // frames got no limb search nor restarts and ended worse than alone on real scans.
    uint32_t iterations = 0, restarts = 0;
    bool cancelled = false, implausible = false;
    std::vector<FitState> starts;
    std::vector<std::vector<double>> shapes;
    for (const Frame& frame : frames) {
        const FitProgress each = [&](uint32_t it, double cost) { return !progress || progress(iterations + it, cost); };
        Solver alone(lin, {frame}, options, pool);
        FitSolution one = alone.run(nullptr, each, std::chrono::steady_clock::now());
        iterations += one.report.iterations;
        restarts += one.report.restarts;
        implausible |= one.report.implausible;
        starts.push_back(one.frames[0]);
        shapes.push_back(one.shape);
        if (one.report.cancelled) {
            cancelled = true;
            break;
        }
    }
    if (cancelled) {  // the frames not reached keep the first frame's fit
        while (starts.size() < frames.size()) starts.push_back(starts[0]);
        FitSolution sol;
        sol.shape = shapes[0];
        sol.frames = starts;
        sol.report.iterations = iterations;
        sol.report.restarts = restarts;
        sol.report.cancelled = true;
        sol.report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return sol;
    }
    std::vector<double> median(shapes[0].size());
    for (std::size_t k = 0; k < median.size(); ++k) {
        std::vector<double> v;
        for (const auto& sh : shapes) v.push_back(sh[k]);
        std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
        median[k] = v[v.size() / 2];
    }
    for (FitState& st : starts) st.shape = median;
    FitOptions joint = options;
    joint.auto_start = false;
    Solver together(lin, frames, joint, pool);
    const FitProgress rest = [&](uint32_t it, double cost) { return !progress || progress(iterations + it, cost); };
    FitSolution sol = together.run(&starts, rest, t0, true);
    sol.report.iterations += iterations;
    sol.report.restarts += restarts;
    sol.report.implausible |= implausible;
    sol.report.converged &= !sol.report.implausible;
    return sol;
}

}  // namespace ssc::fitting
