// The schedule of a fit (see solver.hpp and docs/fitting.md): the start, the coarse-to-fine stages
// (stages.hpp) with the limb and hand searches between them, restarts, the report, and several
// frames fitted alone and then together. What a stage evaluates and solves is fit_problem.hpp's.
#include "fitting/solver.hpp"
#include "fitting/fit_problem.hpp"
#include "fitting/hand_search.hpp"
#include "fitting/limb_search.hpp"
#include "fitting/rigid_start.hpp"

#include "common/error.hpp"
#include "synthesis/shape_range.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <limits>

namespace ssc::fitting {

namespace {

// A start candidate whose short coarse fit ends with pose priors above this is implausible (one
// joint 10 degrees past its limit costs about 38; plausible fits stay near 100 or below).
constexpr double kImplausiblePose = 300;
// A whole fit ending with pose priors above this is implausible, and a single frame's fit from the
// automatic start is then redone from the start search's other candidates, at most kMaxRestarts
// times (see restart_if_implausible()). Of 670 benchmark fits (scan, front depth, front and back
// depth, trials 0-139; 250 more scans) all but two ended between 3 and 27; those two, forced onto
// a body of the other way round, near 300. An upside-down fit seen on the way ended at 98.
constexpr double kImplausibleFit = 50;
constexpr uint32_t kMaxRestarts = 2;
// A limb that gained this fraction of the measure in the limb search has the limbs searched
// before it searched again (see fit_stages(); the measurements are in docs/fitting.md).
constexpr double kResweep = 0.3;
// A one-frame fit leaving more than kRetryUnexplained of its scan unexplained
// (FitProblem::unexplained_share) is redone from the next start candidates; one leaving more than
// kFailedUnexplained is reported as not converged. On the benchmark's scans (1 % outliers, 20 %
// holes; 30 trials) the share ended at 1.4 % or less, on front depth images at 0; retrying from
// 3 % rather than 5 % found two more of the hard poses' failures and flagged no good fit.
constexpr double kRetryUnexplained = 0.03;
constexpr double kFailedUnexplained = 0.10;
// Start candidates that get a short coarse fit at most (the best two always; more while those end
// implausible).
constexpr std::size_t kMaxShortFits = 8;

using Eigen::Quaterniond;

class Solver {
public:
    Solver(const LinearModel& lin, const std::vector<Frame>& frames, const FitOptions& o, ThreadPool* pool)
        : p_(lin, frames, o, pool), o_(o), F_(uint32_t(frames.size())), K_(lin.K), whole_body_(lin.whole_body) {}

    // refine: start from `start` with the fine stages only (the joint refinement of frames fitted
    // one by one, see fit()).
    FitSolution run(const std::vector<FitState>* start, const FitProgress& progress, std::chrono::steady_clock::time_point t0,
                    bool refine = false) {
        FitSolution sol;
        std::vector<double>& shape = p_.shape();
        std::vector<FitState>& states = p_.states();
        shape.assign(K_, 0.0);
        states.assign(F_, p_.kin(0).zero_state());
        if (start && !o_.auto_start) {
            for (uint32_t f = 0; f < F_; ++f) states[f] = (*start)[f];
            for (uint32_t k = 0; k < K_ && k < (*start)[0].shape.size(); ++k)
                shape[k] = within_shape_range((*start)[0].shape[k]);
            for (auto& s : states) s.shape.resize(K_, 0.0);
        } else {
            for (uint32_t f = 0; f < F_; ++f) states[f] = initial_state(f);
            // A single frame keeps the shape its start search fitted (several frames each fitted
            // their own; they start from the mean).
            if (F_ == 1 && searched_frames_ == 1) shape = states[0].shape;
        }
        const Schedule plan = schedule(o_.max_iterations, K_, start && !o_.auto_start, whole_body_);
        bool cancelled = false;
        uint32_t iteration = 0;
        // Frames whose start search ended with a short coarse fit need no rigid stage.
        const int first_stage = refine ? Schedule::kFine : searched_frames_ == F_ ? Schedule::kCoarse : Schedule::kRigid;
        bool converged = fit_stages(plan, first_stage, progress, iteration, cancelled, &sol.report.initial_cost);
        if (F_ == 1 && searched_frames_ == 1 && !cancelled)
            converged = restart_if_implausible(plan, progress, iteration, cancelled, sol.report.restarts, converged);
        if (plan.segment_iterations > 0 && !cancelled) converged = fit_segment_stages(plan, progress, iteration, cancelled, converged);
        report(plan.stages[Schedule::kPolish], converged, sol.report);
        sol.report.iterations = iteration;
        sol.report.cancelled = cancelled;
        sol.shape = shape;
        sol.frames = states;
        for (auto& s : sol.frames) s.shape = shape;
        sol.report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return sol;
    }

private:
    // The report on the final state with the final stage's rules.
    void report(const Stage& last, bool converged, FitReport& r) {
        p_.update_kinematics();
        p_.find_pairs(last);
        r.final_cost = p_.evaluate(last, nullptr, nullptr);
        double lm2 = 0, pd = 0;
        std::size_t nl = 0, np = 0, accepted = 0;
        for (uint32_t f = 0; f < F_; ++f) {
            const FrameData& fd = p_.frame(f);
            const Kinematics& kin = p_.kin(f);
            for (std::size_t i = 0; i < fd.landmark_points.size(); ++i, ++nl)
                lm2 += (kin.point(fd.landmark_points[i]) - fd.landmark_targets[i]).squaredNorm();
            for (const auto& p : fd.pairs) {
                if (!p.model.weight[1]) {
                    pd += (kin.point(p.model) - p.target).norm();
                    ++np;
                }
            }
            accepted += fd.pairs.size();
        }
        const std::size_t tried = p_.pair_queries();
        for (uint32_t f = 0; f < F_; ++f) r.unexplained = std::max(r.unexplained, p_.unexplained_share(f));
        p_.update_kinematics();
        // A fit that leaves this much of a scan unexplained has not found the person: not converged.
        r.converged = converged && r.unexplained <= kFailedUnexplained;
        r.implausible = implausible_;
        r.landmark_rms = nl ? std::sqrt(lm2 / double(nl)) : 0;
        r.point_mean = np ? pd / double(np) : 0;
        r.inlier_fraction = tried ? double(accepted) / double(tried) : 0;
    }

    // The coarse-to-fine stages from stages[first_stage] on, with the limb search between the coarse
    // and the fine stage. Returns whether the fine stage converged.
    bool fit_stages(const Schedule& plan, int first_stage, const FitProgress& progress, uint32_t& iteration, bool& cancelled,
                    double* first_cost) {
        const Stage (&stages)[4] = plan.stages;
        bool converged = false;
        // With segment components the polish waits for them (fit_segment_stages()).
        const int last_stage = plan.segment_iterations > 0 ? Schedule::kFine : Schedule::kPolish;
        for (int si = first_stage; si <= last_stage && !cancelled; ++si) {
            if (stages[si].iterations == 0) continue;
            // The polish has a fixed budget: convergence is the fine stage's.
            const bool stage_converged = p_.run_stage(stages[si], kAllFrames, &progress, iteration, cancelled, first_cost);
            if (si < Schedule::kPolish) converged = stage_converged;
            // After the fine stage, with the wrists in place: how closed each hand is, and when a
            // hand changed, the fine stage again from there.
            if (si == Schedule::kFine && o_.hand_search && !cancelled && search_hands()) {
                Stage again = stages[Schedule::kFine];
                again.iterations = std::max<uint32_t>(2, again.iterations / 2);
                converged = p_.run_stage(again, kAllFrames, &progress, iteration, cancelled);
            }
            // Between the coarse and the fine stage: limbs the coarse stage could not reach, each
            // search settled by a short coarse stage when a limb moved. Limbs are searched one after
            // another, so a limb that gained kResweep of the measure (a raised leg found) changed
            // what the limbs searched before it had to explain: they are searched again.
            if (si == Schedule::kCoarse && !cancelled) {
                Stage again = stages[Schedule::kCoarse];
                again.iterations = std::max<uint32_t>(1, again.iterations / 2);
                std::size_t count = kLimbCount;
                for (int sweep = 0; sweep < 2 && count > 0 && !cancelled; ++sweep) {
                    const LimbGains gains = search_limbs(count);
                    if (*std::max_element(gains.begin(), gains.end()) > 0) p_.run_stage(again, kAllFrames, &progress, iteration, cancelled);
                    const std::size_t searched = count;
                    count = 0;  // the limbs before the last that gained kResweep
                    for (std::size_t i = 0; i < searched; ++i)
                        if (gains[i] >= kResweep) count = i;
                }
            }
        }
        return converged;
    }

    // What restart_if_implausible() accepts of a frame: its pose prior and unexplained share.
    static bool acceptable(double pose_prior, double unexplained) { return pose_prior <= kImplausibleFit && unexplained <= kRetryUnexplained; }
    bool every_frame_acceptable() {
        for (uint32_t f = 0; f < F_; ++f)
            if (!acceptable(p_.pose_priors(f), p_.unexplained_share(f))) return false;
        return true;
    }

    // The segment components (a LinearModel's beyond its whole body's) join a fit that the whole
    // body's components have settled and restart_if_implausible() has checked: the fine stage with
    // every component, then the polish. Fitted earlier, the segments took up part of a misplaced
    // limb's error (an arm 13 to 21 mm off its scan left 2.5 % of the scan unexplained, under the
    // restart's 3 %), so the failure went unnoticed. A fit that was acceptable and that they make
    // unacceptable keeps its whole-body result. Returns whether the kept fit converged.
    bool fit_segment_stages(const Schedule& plan, const FitProgress& progress, uint32_t& iteration, bool& cancelled, bool converged) {
        p_.update_kinematics();
        const std::vector<double> shape_before = p_.shape();
        const std::vector<FitState> states_before = p_.states();
        const bool acceptable_before = every_frame_acceptable();
        Stage segments = plan.stages[Schedule::kFine];
        segments.components = K_;
        segments.iterations = plan.segment_iterations;
        bool with_segments = p_.run_stage(segments, kAllFrames, &progress, iteration, cancelled);
        if (!cancelled && plan.stages[Schedule::kPolish].iterations > 0)
            p_.run_stage(plan.stages[Schedule::kPolish], kAllFrames, &progress, iteration, cancelled);
        p_.update_kinematics();
        if (acceptable_before && !every_frame_acceptable() && !cancelled) {
            p_.shape() = shape_before;
            p_.states() = states_before;
            p_.update_kinematics();
            return converged;
        }
        return with_segments && !implausible_;
    }

    // A single frame's fit from the automatic start that ends implausible (joints far past their
    // limits: a body forced onto data of the other way round) or leaves more than
    // kRetryUnexplained of its scan unexplained (a limb or the body in the wrong place) is redone from the start search's
    // other candidates, best first, until one ends plausible (kMaxRestarts). The kept fit is the
    // first plausible one, else the one explaining the cloud best; a cancelled restart keeps the
    // fits before it. Restarts are rare (2 of 670 benchmark fits, each then fixed: 545 and 541 mm
    // mean vertex error to 1.6 and 1.1) and each costs a fit. Returns whether the kept fit converged.
    bool restart_if_implausible(const Schedule& plan, const FitProgress& progress, uint32_t& iteration, bool& cancelled,
                                uint32_t& restarts, bool converged) {
        p_.update_kinematics();
        const double prior = p_.pose_priors(0), unexplained = p_.unexplained_share(0);
        if (acceptable(prior, unexplained)) return converged;
        struct Attempt {
            std::vector<double> shape;
            std::vector<FitState> states;
            bool converged;
            double prior, unexplained, measure;
        };
        Attempt best{p_.shape(), p_.states(), converged, prior, unexplained, p_.explained(0)};
        // The start poses not tried yet get their short fits now; all candidates, best first.
        std::vector<std::pair<double, FitState>> alternatives = alternative_starts_;
        double best_cost = std::numeric_limits<double>::infinity(), best_prior = 0;
        for (const auto& [t, found] : deferred_templates_) {
            best_prior = 0;
            short_fits(0, found, &p_.templates().posed()[t].pose, alternatives, best_cost, best_prior);
        }
        std::stable_sort(alternatives.begin(), alternatives.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        for (const auto& [cost, alternative] : alternatives) {
            if (acceptable(best.prior, best.unexplained) || restarts == kMaxRestarts) break;
            p_.states()[0] = alternative;
            p_.shape() = alternative.shape;
            const bool c = fit_stages(plan, Schedule::kCoarse, progress, iteration, cancelled, nullptr);
            if (cancelled) break;
            ++restarts;
            p_.update_kinematics();
            const double p = p_.pose_priors(0), u = p_.unexplained_share(0), measure = p_.explained(0);
            if (acceptable(p, u) || measure < best.measure) best = {p_.shape(), p_.states(), c, p, u, measure};
        }
        p_.shape() = best.shape;
        p_.states() = best.states;
        p_.update_kinematics();
        // Still implausible after the restarts: most likely a limb or the body in the wrong place
        // (benchmark poses crouching and bent over), reported as failed.
        implausible_ = !cancelled && !acceptable(best.prior, best.unexplained);
        return best.converged && !implausible_;
    }

    // Short coarse fits (pose and the main shape components) of a template's rigid candidates,
    // best first: the two best, more while the best so far ends implausible (at most
    // kMaxShortFits). Each result joins `checked` with its explained measure.
    void short_fits(uint32_t f, const std::vector<StartCandidate>& found, const std::vector<Quaterniond>* pose,
                    std::vector<std::pair<double, FitState>>& checked, double& best_cost, double& best_prior) {
        const Stage coarse = start_stage(std::min(K_, kCoarseComponents));
        for (std::size_t i = 0; i < found.size(); ++i) {
            if ((i >= 2 && best_prior <= kImplausiblePose) || i >= kMaxShortFits) break;
            std::fill(p_.shape().begin(), p_.shape().end(), 0.0);
            p_.states()[f] = p_.placed(f, found[i].placement, pose);
            uint32_t iterations = 0;
            bool cancelled = false;
            p_.run_stage(coarse, f, nullptr, iterations, cancelled);
            p_.update_kinematics();
            p_.find_pairs(coarse, f);
            const double cost = p_.explained(f);
            checked.emplace_back(cost, p_.states()[f]);
            if (cost < best_cost) best_cost = cost, best_prior = p_.pose_priors(f);
        }
    }

    FitState initial_state(uint32_t f) {
        const FrameData& fd = p_.frame(f);
        if (fd.landmark_points.size() >= 3) {
            FitState s = p_.kin(f).zero_state();
            p_.kin(f).update(s);
            Eigen::Matrix3Xd src(3, fd.landmark_points.size()), dst(3, fd.landmark_points.size());
            for (std::size_t i = 0; i < fd.landmark_points.size(); ++i) {
                src.col(Eigen::Index(i)) = p_.kin(f).point(fd.landmark_points[i]);
                dst.col(Eigen::Index(i)) = fd.landmark_targets[i];
            }
            return p_.placed(f, align_points(src, dst, o_.fit_scale));
        }
        // No landmarks: the rigid start search (rigid_start.hpp) over the mean body at rest.
        RigidStartOptions ro;
        ro.fit_scale = o_.fit_scale;
        ro.point_sigma = o_.point_sigma;
        ro.points = std::size_t(0.15 * o_.max_points);
        ro.samples = kExplainedSamples;
        p_.build_start_grid(f);
        // The rigid measure tells front from back far worse than a short coarse fit does: the best
        // candidates get one (short_fits). (One scan of 390 had its right heading ranked last by
        // the rigid measure.)
        ++searched_frames_;
        double best_cost = std::numeric_limits<double>::infinity(), best_prior = 0;
        std::vector<std::pair<double, FitState>> checked;  // explained measure after the short fit, state
        const std::vector<StartCandidate> at_rest = rigid_start(p_.templates().rest(), p_.cloud_view(f), ro, p_.pool());
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
        for (std::size_t t = 0; t < p_.templates().posed().size(); ++t) {
            std::vector<StartCandidate> posed = rigid_start(p_.templates().posed()[t].sample(), p_.cloud_view(f), quick, p_.pool());
            if (posed.front().score >= at_rest.front().score && best_prior <= kImplausiblePose) {
                if (F_ == 1) deferred_templates_.emplace_back(t, std::move(posed));
                continue;
            }
            const double prior = best_prior;
            best_prior = 0;  // the template's best two at least
            short_fits(f, posed, &p_.templates().posed()[t].pose, checked, best_cost, best_prior);
            best_prior = std::min(best_prior, prior);
        }
        // Best first (the first of equals): the start, then the others for restarts (run()).
        std::stable_sort(checked.begin(), checked.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        if (F_ == 1) alternative_starts_.assign(checked.begin() + 1, checked.end());
        std::fill(p_.shape().begin(), p_.shape().end(), 0.0);
        return checked.front().second;
    }

    // Arms and legs the coarse stage cannot reach (limb_search.hpp): the first `count` limbs, for
    // every frame with a cloud. Returns each limb's largest relative gain over the frames.
    LimbGains search_limbs(std::size_t count) {
        LimbGains gains{};
        for (uint32_t f = 0; f < F_; ++f)
            if (p_.has_points(f)) {
                const LimbGains g = fitting::search_limbs(p_.kin(f), p_.body(), p_.states()[f], p_.cloud_view(f), p_.vertex_sample(), p_.pool(), count);
                for (std::size_t i = 0; i < kLimbCount; ++i) gains[i] = std::max(gains[i], g[i]);
            }
        p_.update_kinematics();
        return gains;
    }

    // How closed each hand is (hand_search.hpp), for every frame with a cloud.
    // Returns whether a hand changed.
    bool search_hands() {
        bool changed = false;
        for (uint32_t f = 0; f < F_; ++f)
            if (p_.has_points(f)) {
                const double* closure = p_.states()[f].hand_closure;
                const double before[2] = {closure[0], closure[1]};
                fitting::search_hands(p_.kin(f), p_.body(), p_.states()[f], p_.cloud_view(f), p_.vertex_sample());
                changed |= before[0] != closure[0] || before[1] != closure[1];
            }
        p_.update_kinematics();
        return changed;
    }

    FitProblem p_;
    FitOptions o_;
    uint32_t F_, K_, whole_body_;
    uint32_t searched_frames_ = 0;  // frames started by the cloud start search (with its coarse fit)
    // A single frame's other start candidates after their short fits, with the explained measure
    // (run()), and the start poses whose short fits were put off (initial_state()).
    std::vector<std::pair<double, FitState>> alternative_starts_;
    std::vector<std::pair<std::size_t, std::vector<StartCandidate>>> deferred_templates_;
    bool implausible_ = false;  // restart_if_implausible found no acceptable fit
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
