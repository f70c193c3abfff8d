// The schedule of a fit (see solver.hpp and docs/fitting.md): the start, the coarse-to-fine stages
// (stages.hpp) with the limb and hand searches between them, restarts, the report, and several
// frames fitted alone and then together. What a stage evaluates and solves is fit_problem.hpp's.
#include "fitting/solver.hpp"
#include "fitting/fit_problem.hpp"
#include "fitting/extremities.hpp"
#include "fitting/forearm_length.hpp"
#include "fitting/hand_search.hpp"
#include "fitting/head_search.hpp"
#include "fitting/judgement.hpp"
#include "fitting/limb_search.hpp"
#include "fitting/rigid_start.hpp"
#include "fitting/wrist_search.hpp"

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
// A single frame's fit from the automatic start that judgement.hpp finds wrong is redone from the
// start search's other candidates, at most kMaxRestarts times, then from the start poses placed
// again and from the extremity start (see restart_if_implausible()).
constexpr uint32_t kMaxRestarts = 2;
// A limb that gained this fraction of the measure in the limb search has the limbs searched
// before it searched again (see fit_stages(); the measurements are in docs/fitting.md).
constexpr double kResweep = 0.3;
// Start candidates that get a short coarse fit at most (the best two always; more while those end
// implausible).
constexpr std::size_t kMaxShortFits = 8;
// After those restarts, the start poses placed again with this many rigid steps (placed_again()),
// at most kPlacedAgainRestarts restarts from them. Pose library (192 fits): 12 steps 68 -> 70 %
// success, 25 -> 15 reported; 20 steps the same 70 %; 4 restarts 70 %, one more silent failure.
constexpr int kPlacedAgainSteps = 12;
constexpr std::size_t kPlacedAgainRestarts = 2;
// ... not when the best fit so far leaves more than this share of the scan unexplained: that is
// more than one person folded wrong (the library's fits that the placed-again restarts fixed left
// 1-23 % unexplained before them; the tests' two people 67-70 %, things that are no person 46 and
// 55 %).
constexpr double kPlacedAgainUnexplained = 0.40;
// A hand closed at least this much (hand_search.hpp) is tried open on a forearm shortened by up to
// kForearmSteps steps of kForearmStep metres, in reopen_closed_hands(). On the pose library (4
// trials, 192 fits): 70 -> 75 % success, 10 -> 9 silent failures, 19 fits better and 2 worse (both
// failed either way) by more than 0.3 mm; most of them one person's right forearm, fitted 4.5 cm
// too long with the hand closed at its end. Every shortening of 0, 3, 6, 9 cm tried, or grids to
// 6 or 8 cm: the same success; steps while they gain, at half the fine stages (docs/fitting.md).
// With landmarks too (no hand landmarks): 93 -> 96 % success, 6 fits 3-6 mm better, none worse.
constexpr double kReopenClosure = 0.375;
constexpr double kForearmStep = 0.03;
constexpr int kForearmSteps = 3;
// Metres: scan points farther than this from a fit count this much in the check of a turned head
// or wrist (keep_if_closer), so a limb off its points elsewhere does not swamp the part's.
constexpr double kMoveCheckCap = 0.02;
// The segment components are kept when the scan lies this much closer with them (its mean distance
// to the fit along the nearest vertex's normal, after / before; fit_segment_stages()). On bodies
// the whole-body components hold (the benchmark's scan scenario, 30 trials) they brought it 0.97
// to 1.00 times as close, fitting noise (mean vertex error 1.89 -> 2.14 mm when kept); on MakeHuman
// people beyond the model 0.72-0.85 times (docs/fitting.md).
constexpr double kSegmentsCloser = 0.95;
// A fit judged right that leaves over kRetryTight of its scan beyond kTightDistance (judgement.hpp)
// is tried again: the limbs searched from it, each arm turned over (turn_arm_over), then up to
// kTightRestarts of the start search's other candidates, each through every stage; a try judged
// right that leaves at most kTightCloser times as much of the scan that far off replaces it
// (restart_if_off_closely()). On the pose library
// (MakeHuman people, 192 fits) 6 fits were tried again and 3 replaced (two silent failures to
// successes, one 30 -> 18 mm), none made worse; at 1.2 % instead of 1.8 a third of the fits were
// tried again for one success more (docs/fitting.md).
constexpr double kTightCloser = 0.8;
// ... and only when over kTightArm of the scan points nearest an arm's vertices (upper arm and
// forearm; the hands are no region) lie that far off (FitProblem::region_shares_beyond_plane):
// what the tries mend is an arm placed wrong. The library's fits that they mended or were made
// for: 5.3-22 % of an arm's points; bumpy simulated scans (the tests'): an arm at most 1 %, the
// head or a leg 6-14 %, which cost four fits' time each for nothing (docs/fitting.md).
constexpr double kTightArm = 0.04;
constexpr std::size_t kTightRestarts = 3;
// The extremity start (extremities.hpp): extremities picked on the scan, labellings tried (each a
// short fit), and how closely the tip stage draws the template's tips to them (metres).
constexpr std::size_t kExtremityPicks = 6, kTipLabellings = 2;
constexpr double kTipSigma = 0.03;
constexpr std::size_t kExtremityPoints = 30000;
// Landmarks that pose the body before the scan is fitted (landmark_stage): enough to place the
// trunk and every limb.
constexpr std::size_t kPosingLandmarks = 12;

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
        given_start_ = start && !o_.auto_start;
        if (given_start_) {
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
        // Segment components (a LinearModel's beyond its whole body's) join only where there are
        // points: landmarks alone do not say how a part is shaped (67 landmarks at 10 mm: 13.7 ->
        // 14.1 mm mean vertex error with them on the benchmark's model bodies).
        bool points = false;
        for (uint32_t f = 0; f < F_; ++f) points |= p_.has_points(f);
        const Schedule plan = schedule(o_.max_iterations, points ? K_ : whole_body_, given_start_, whole_body_);
        bool cancelled = false;
        uint32_t iteration = 0;
        if (!given_start_ && !refine)
            for (uint32_t f = 0; f < F_ && !cancelled; ++f)
                if (p_.frame(f).own_landmarks >= kPosingLandmarks && p_.has_points(f))
                    p_.run_stage(landmark_stage(), f, &progress, iteration, cancelled);
        // Frames whose start search ended with a short coarse fit need no rigid stage.
        const int first_stage = refine ? Schedule::kFine : searched_frames_ == F_ ? Schedule::kCoarse : Schedule::kRigid;
        bool converged = fit_stages(plan, first_stage, progress, iteration, cancelled, &sol.report.initial_cost);
        if (F_ == 1 && searched_frames_ == 1 && !cancelled)
            converged = restart_if_implausible(plan, progress, iteration, cancelled, sol.report.restarts, converged);
        if (plan.segment_iterations > 0 && !cancelled) converged = fit_segment_stages(plan, progress, iteration, cancelled, converged);
        if (F_ == 1 && searched_frames_ == 1 && !cancelled && p_.has_points(0))
            converged = restart_if_off_closely(plan, progress, iteration, cancelled, sol.report.restarts, converged);
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
        r.frames.clear();
        for (uint32_t f = 0; f < F_; ++f) {
            const Judgement j = judge(p_, f, true, wrists_searched());
            r.unexplained = std::max(r.unexplained, j.unexplained);
            FrameReport fr;
            fr.problem = j.problem;
            fr.problem_text = j.describe(p_.linear().model);
            fr.unscanned = j.unscanned_parts();
            fr.unexplained = j.unexplained;
            fr.joint = j.joint;
            fr.joint_excess = j.joint_excess;
            fr.coverage = j.coverage;
            fr.loose = j.loose;
            for (std::size_t g = 0; g < kBodyRegionCount; ++g)
                if (g != std::size_t(BodyRegion::Trunk)) fr.off_scan = std::max(fr.off_scan, j.off_scan[g]);
            fr.region = j.region;
            fr.failed = !j.acceptable();
            if (fr.failed && r.problem == FitProblemKind::None) r.problem = j.problem, r.problem_text = fr.problem_text;
            if (r.unscanned.empty()) r.unscanned = fr.unscanned;
            r.frames.push_back(std::move(fr));
        }
        p_.update_kinematics();
        bool any_failed = false;
        for (const FrameReport& fr : r.frames) any_failed |= fr.failed;
        // A fit judged wrong (judgement.hpp) has not converged to the person, whatever its cost did.
        r.converged = converged && !any_failed;
        r.implausible = implausible_ || any_failed;
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
            // hand changed, the fine stage again from there. In a single frame's fit from its own
            // start (the automatic one or the landmarks') a closed hand is then checked against
            // the fit before it (keep_if_closer): on a hand the stages before left off its points
            // a fist scores best, its fingers pulled out of empty space (pose library: 42 of 384
            // open hands closed, 91 mm off); a true fist brings the scan closer. Not in a
            // sequence's tracked frames (capture benchmark: 4 more frames good, 1 more silent).
            // The head's turn likewise (head_search.hpp), in fits from the automatic start as the
            // restarts: from a given start (a sequence's tracked frames) it turned heads wrong and
            // the frames after them followed (capture benchmark: 78 -> 70 of 100 frames good).
            // A turned head is checked against the fit before it (keep_if_closer); then the wrists.
            if (si == Schedule::kFine && !cancelled) {
                const bool automatic_start = wrists_searched();
                Stage again = stages[Schedule::kFine];
                again.iterations = std::max<uint32_t>(2, again.iterations / 2);
                bool fine_converged = converged;
                std::vector<double> shape_fitted = p_.shape();
                std::vector<FitState> fitted = p_.states();
                bool hands = o_.hand_search && search_hands();
                if (hands && F_ == 1 && !given_start_ && !cancelled) {
                    converged = p_.run_stage(again, kAllFrames, &progress, iteration, cancelled);
                    if (!cancelled)
                        keep_if_closer(shape_fitted, fitted, nullptr, again, fine_converged, progress, iteration, cancelled, converged);
                    hands = false;  // settled, or undone: the head's check starts from here
                    shape_fitted = p_.shape(), fitted = p_.states(), fine_converged = converged;
                }
                if (F_ == 1 && !given_start_ && o_.hand_search && !cancelled && reopen_closed_hands(again, progress, iteration, cancelled, converged))
                    shape_fitted = p_.shape(), fitted = p_.states(), fine_converged = converged;
                const std::vector<FitState> hands_set = p_.states();
                const bool turned = automatic_start && search_head();
                if (hands || turned) converged = p_.run_stage(again, kAllFrames, &progress, iteration, cancelled);
                if (turned && !cancelled)
                    keep_if_closer(shape_fitted, fitted, hands ? &hands_set : nullptr, again, fine_converged, progress, iteration, cancelled, converged);
                // Then the forearms' turns and the wrists (wrist_search.hpp), checked the same way.
                if (automatic_start && !cancelled) {
                    const bool settled_converged = converged;
                    const std::vector<double> shape_settled = p_.shape();
                    const std::vector<FitState> settled = p_.states();
                    if (fitting::search_wrists(p_.kin(0), p_.body(), p_.states()[0], p_.cloud_view(0), p_.vertex_sample(), p_.pool())) {
                        p_.update_kinematics();
                        converged = p_.run_stage(again, kAllFrames, &progress, iteration, cancelled);
                        if (!cancelled)
                            keep_if_closer(shape_settled, settled, nullptr, again, settled_converged, progress, iteration, cancelled, converged);
                    }
                }
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

    // After the hand, head or wrist search moved a part and the fine stage ran again: the move is
    // kept only when the fit now lies closer to the scan (FitProblem::mean_scan_distance, single
    // frame); else the fit from before it comes back (with the hand search's closures, fitted
    // again). A part's own measure cannot always tell a turn (a round head on a scan with holes, a
    // hand that differs from the model's by 18 mm): on the pose library a wrong turn left the whole
    // fit farther from its points (docs/fitting.md).
    void keep_if_closer(const std::vector<double>& shape_before, const std::vector<FitState>& before, const std::vector<FitState>* hands_set,
                        const Stage& again, bool converged_before, const FitProgress& progress, uint32_t& iteration, bool& cancelled,
                        bool& converged) {
        const double moved_distance = p_.mean_scan_distance(0, kMoveCheckCap);
        std::vector<double> shape_moved = std::move(p_.shape());
        std::vector<FitState> moved = std::move(p_.states());
        p_.shape() = shape_before;
        p_.states() = before;
        if (moved_distance <= p_.mean_scan_distance(0, kMoveCheckCap)) {
            p_.shape() = std::move(shape_moved);
            p_.states() = std::move(moved);
        } else {
            converged = converged_before;
            if (hands_set) {
                for (uint32_t f = 0; f < F_; ++f)
                    std::copy((*hands_set)[f].hand_closure, (*hands_set)[f].hand_closure + 2, p_.states()[f].hand_closure);
                converged = p_.run_stage(again, kAllFrames, &progress, iteration, cancelled);
            }
        }
        p_.update_kinematics();
    }

    // A hand the hand search closed may stand for a forearm fitted too long (forearm_length.hpp):
    // each hand closed at least kReopenClosure is opened on its forearm shortened by kForearmStep,
    // then by further steps while each brings the scan closer (or, when the first does not, on the
    // forearm as it is), the fine stage again from each; the fit that lies closest to the scan
    // (mean_scan_distance, as keep_if_closer) is kept, the closed hand among them. Single frames
    // from their own start, the automatic one or the landmarks' (with landmarks: 93 -> 96 % on the
    // pose library). Returns whether a hand was opened.
    bool reopen_closed_hands(const Stage& again, const FitProgress& progress, uint32_t& iteration, bool& cancelled, bool& converged) {
        bool opened = false;
        const Model& model = p_.linear().model;
        for (int hand = 0; hand < 2 && !cancelled; ++hand) {
            if (p_.states()[0].hand_closure[hand] < kReopenClosure) continue;
            const std::vector<double> shape_closed = p_.shape();
            const std::vector<FitState> closed = p_.states();
            double best = p_.mean_scan_distance(0, kMoveCheckCap);
            std::vector<double> best_shape;
            std::vector<FitState> best_states;
            bool best_converged = converged;
            // Whether the hand opened on the forearm shortened by `shortening` is the best yet.
            auto attempt = [&](double shortening) {
                const std::vector<double> change = forearm_length_change(p_.linear(), shape_closed, hand, -shortening);
                if (change.empty() || cancelled) return false;
                p_.shape() = shape_closed;
                p_.states() = closed;
                for (std::size_t k = 0; k < change.size(); ++k) p_.shape()[k] = within_shape_range(p_.shape()[k] + change[k]);
                set_hand_closure(model, p_.states()[0], hand, 0.0);
                p_.update_kinematics();
                const bool stage_converged = p_.run_stage(again, kAllFrames, &progress, iteration, cancelled);
                if (cancelled) return false;
                const double distance = p_.mean_scan_distance(0, kMoveCheckCap);
                if (distance >= best) return false;
                best = distance, best_shape = p_.shape(), best_states = p_.states(), best_converged = stage_converged;
                return true;
            };
            // Shorter while each step brings the scan closer; a first step that does not, the hand
            // opened on the forearm as it is instead.
            if (attempt(kForearmStep)) {
                for (int step = 2; step <= kForearmSteps; ++step)
                    if (!attempt(step * kForearmStep)) break;
            } else {
                attempt(0.0);
            }
            if (best_states.empty() || cancelled) {
                p_.shape() = shape_closed;
                p_.states() = closed;
            } else {
                p_.shape() = std::move(best_shape);
                p_.states() = std::move(best_states);
                converged = best_converged;
                opened = true;
            }
            p_.update_kinematics();
        }
        return opened;
    }

    // A single frame from the fit's own start: its head and wrists are searched (fit_stages), and
    // its hands judged (judge()'s hands).
    bool wrists_searched() const { return F_ == 1 && searched_frames_ == 1; }

    // What restart_if_implausible() accepts of a frame: judgement.hpp's verdict.
    bool every_frame_acceptable() {
        for (uint32_t f = 0; f < F_; ++f)
            if (!judge(p_, f).acceptable()) return false;
        return true;
    }

    // The segment components (a LinearModel's beyond its whole body's) join a fit that the whole
    // body's components have settled and restart_if_implausible() has checked: the fine stage with
    // every component, then the polish. Fitted earlier, the segments took up part of a misplaced
    // limb's error (an arm 13 to 21 mm off its scan left 2.5 % of the scan unexplained, under the
    // restart's 3 %), so the failure went unnoticed. A fit that was acceptable and that they make
    // unacceptable keeps its whole-body result. Unless FitOptions::keep_segments_always, they are
    // also kept only when the scan then lies kSegmentsCloser closer (scan_distance()). A whole-body
    // result that comes back gets the rest of its fine stage and its polish. Returns whether the
    // kept fit converged.
    bool fit_segment_stages(const Schedule& plan, const FitProgress& progress, uint32_t& iteration, bool& cancelled, bool converged) {
        p_.update_kinematics();
        const std::vector<double> shape_before = p_.shape();
        const std::vector<FitState> states_before = p_.states();
        const bool acceptable_before = every_frame_acceptable();
        const double distance_before = o_.keep_segments_always ? 0 : scan_distance();
        Stage segments = plan.stages[Schedule::kFine];
        segments.components = K_;
        segments.iterations = plan.segment_iterations;
        const bool with_segments = p_.run_stage(segments, kAllFrames, &progress, iteration, cancelled);
        if (!cancelled && plan.stages[Schedule::kPolish].iterations > 0)
            p_.run_stage(plan.stages[Schedule::kPolish], kAllFrames, &progress, iteration, cancelled);
        if (cancelled) return with_segments && !implausible_;
        p_.update_kinematics();
        const bool closer = o_.keep_segments_always || scan_distance() <= kSegmentsCloser * distance_before;
        if (closer && (!acceptable_before || every_frame_acceptable())) return with_segments && !implausible_;
        p_.shape() = shape_before;
        p_.states() = states_before;
        Stage rest = segments, polish = plan.stages[Schedule::kPolish];
        rest.components = polish.components = whole_body_;
        converged = p_.run_stage(rest, kAllFrames, &progress, iteration, cancelled);
        if (!cancelled && polish.iterations > 0) p_.run_stage(polish, kAllFrames, &progress, iteration, cancelled);
        p_.update_kinematics();
        return converged && !implausible_;
    }

    // The mean distance of the scan points to the fit along the nearest vertices' normals
    // (FitProblem::mean_scan_plane_distance) over the frames with points, weighted by their points;
    // 0 without any.
    double scan_distance() {
        double sum = 0;
        std::size_t n = 0;
        for (uint32_t f = 0; f < F_; ++f)
            if (p_.has_points(f)) {
                const std::size_t m = p_.frame(f).points.size();
                sum += p_.mean_scan_plane_distance(f, kMoveCheckCap) * double(m), n += m;
            }
        return n ? sum / double(n) : 0;
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
        const Judgement first = judge(p_, 0);
        // Settled: judged right and the scan tightly explained (kRetryLoose). A fit judged right
        // but loose is redone too; a restart replaces the best so far when it is judged right and
        // that one is not, when neither is and it explains the scan better, or when both are and it
        // explains the scan better and leaves less of it loose (a crouching fit at 1.7 mm, 2.7 %
        // loose, was replaced by one explaining 1 % better, as loose, at 6.3 mm).
        const auto settled = [](const Judgement& j) { return j.acceptable() && j.loose <= kRetryLoose; };
        const auto better = [](const Judgement& j, double measure, const Judgement& than, double than_measure) {
            if (j.acceptable() != than.acceptable()) return j.acceptable();
            return measure < than_measure && (!j.acceptable() || j.loose < than.loose);
        };
        if (settled(first)) return converged;
        struct Attempt {
            std::vector<double> shape;
            std::vector<FitState> states;
            bool converged;
            Judgement judgement;
            double measure;
        };
        Attempt best{p_.shape(), p_.states(), converged, first, p_.explained(0)};
        const std::vector<std::pair<double, FitState>> alternatives = other_starts();
        const auto by_measure = [](const auto& a, const auto& b) { return a.first < b.first; };
        // Each restart: the fit from the candidate, kept when judged right or explaining more.
        const auto restart_from = [&](const FitState& alternative) {
            p_.states()[0] = alternative;
            p_.shape() = alternative.shape;
            const bool c = fit_stages(plan, Schedule::kCoarse, progress, iteration, cancelled, nullptr);
            if (cancelled) return;
            ++restarts;
            p_.update_kinematics();
            const Judgement j = judge(p_, 0);
            const double measure = p_.explained(0);
            if (better(j, measure, best.judgement, best.measure)) best = {p_.shape(), p_.states(), c, j, measure};
        };
        for (const auto& [cost, alternative] : alternatives) {
            if (settled(best.judgement) || restarts == kMaxRestarts || cancelled) break;
            restart_from(alternative);
        }
        // A further set of candidates, best first, each a restart more until one settles (at most `limit`).
        const auto restart_best_first = [&](std::vector<std::pair<double, FitState>> candidates, std::size_t limit) {
            std::stable_sort(candidates.begin(), candidates.end(), by_measure);
            for (std::size_t i = 0; i < candidates.size() && i < limit; ++i) {
                if (settled(best.judgement) || cancelled) break;
                restart_from(candidates[i].second);
            }
        };
        // Then the start poses placed again, more carefully (placed_again()), for a fit still judged
        // wrong: one judged right but loose is no body folded wrong (none of the pose library's 192
        // fits came here judged right; fits of a model without its shape space do, four in one test
        // whose time under the sanitizers this halved).
        if (!best.judgement.acceptable() && best.judgement.unexplained <= kPlacedAgainUnexplained && !cancelled)
            restart_best_first(placed_again(), kPlacedAgainRestarts);
        // Then the extremity start's candidates: after the templates', so that a fit they fix is
        // fixed as before (ranked among them by the explained measure, the extremity start took
        // their restarts and left fits they fixed failed).
        if (!settled(best.judgement) && !cancelled) {
            std::vector<std::pair<double, FitState>> extremity;
            extremity_fits(0, extremity);
            restart_best_first(std::move(extremity), std::numeric_limits<std::size_t>::max());
        }
        p_.shape() = best.shape;
        p_.states() = best.states;
        p_.update_kinematics();
        // Still implausible after the restarts: most likely a limb or the body in the wrong place
        // (benchmark poses crouching and bent over), reported as failed.
        implausible_ = !cancelled && !best.judgement.acceptable();
        return best.converged && !implausible_;
    }

    // A single frame's finished fit from the automatic start (every stage, the segments' too) that is
    // judged right but leaves over kRetryTight of its scan a little way off: a hand or forearm
    // placed wrong as a whole lies on the scan within the judgement's distances, yet leaves more of
    // the scan 8 mm off than any good fit on the pose library. Tried again, from the fit itself with
    // its limbs searched (the limb search between the coarse and fine stages posed them on a trunk
    // not yet settled), then from the start search's next candidates; a try replaces the fit only
    // when judged right and leaving kTightCloser as much of the scan off, so a good fit is never
    // traded for a worse one and nothing is reported failed for it: real scans with clothes or hair
    // leave more of the scan off than simulated ones, and then only cost the tries' time. Returns
    // whether the kept fit converged.
    bool restart_if_off_closely(const Schedule& plan, const FitProgress& progress, uint32_t& iteration, bool& cancelled,
                                uint32_t& restarts, bool converged) {
        p_.update_kinematics();
        if (!judge(p_, 0).acceptable()) return converged;
        const double off = p_.share_beyond_plane(0, kTightDistance, kTightCap);
        if (off <= kRetryTight) return converged;
        // ... and only when an arm holds it (kTightArm): what the tries below mend is an arm placed
        // wrong. A scan's own bumps (hair, clothes; the tests' simulated bumps) leave a head or a
        // leg off and would cost four fits' time for nothing.
        const std::vector<double> regions = p_.region_shares_beyond_plane(0, kTightDistance, kTightCap, p_.vertex_regions(), kBodyRegionCount);
        if (std::max(regions[std::size_t(BodyRegion::LeftArm)], regions[std::size_t(BodyRegion::RightArm)]) <= kTightArm) return converged;
        struct Kept {
            std::vector<double> shape;
            std::vector<FitState> states;
            bool converged;
            double off;
        };
        Kept best{p_.shape(), p_.states(), converged, off};
        const auto consider = [&](bool c) {
            ++restarts;
            p_.update_kinematics();
            const double t = p_.share_beyond_plane(0, kTightDistance, kTightCap);
            // Never a converged fit traded for one that did not converge: the fit would then be
            // reported failed for a retry (the model's own squat with the arms raised: 5.50 mm
            // converged -> 8.40 mm unconverged, an arm turned over).
            if (t < kTightCloser * best.off && (c || !best.converged) && judge(p_, 0, true, wrists_searched()).acceptable())
                best = {p_.shape(), p_.states(), c, t};
            p_.shape() = best.shape;
            p_.states() = best.states;
            p_.update_kinematics();
        };
        // Every component's fine stage and the polish from a moved fit; whether it converged.
        const auto settle = [&]() {
            Stage all = plan.stages[Schedule::kFine];
            all.components = K_;
            if (plan.segment_iterations > 0) all.iterations = plan.segment_iterations;
            const bool c = p_.run_stage(all, kAllFrames, &progress, iteration, cancelled);
            if (!cancelled && plan.stages[Schedule::kPolish].iterations > 0)
                p_.run_stage(plan.stages[Schedule::kPolish], kAllFrames, &progress, iteration, cancelled);
            return c;
        };
        // The limbs searched from the finished fit, then settled.
        const LimbGains gains = search_limbs(kLimbCount);
        if (*std::max_element(gains.begin(), gains.end()) > 0) {
            const bool c = settle();
            if (cancelled) return restore(best.shape, best.states), best.converged;
            consider(c);
        } else {
            restore(best.shape, best.states);
        }
        // Each arm turned half a turn about the line from its shoulder to its wrist, then settled:
        // a straight arm turned over (the palm and the elbow facing the other way) lies on its
        // points nearly as well, and no descent step turns it back through the half turn.
        for (const anatomy::Side side : {anatomy::Side::Left, anatomy::Side::Right}) {
            if (cancelled || !turn_arm_over(p_.kin(0), p_.states()[0], side)) continue;
            p_.update_kinematics();
            const bool c = settle();
            if (cancelled) return restore(best.shape, best.states), best.converged;
            consider(c);
        }
        // The start search's next candidates, each through every stage.
        const std::vector<std::pair<double, FitState>> alternatives = other_starts();
        for (std::size_t i = 0; i < alternatives.size() && i < kTightRestarts && !cancelled; ++i) {
            p_.states()[0] = alternatives[i].second;
            p_.shape() = alternatives[i].second.shape;
            bool c = fit_stages(plan, Schedule::kCoarse, progress, iteration, cancelled, nullptr);
            if (!cancelled && plan.segment_iterations > 0) c = fit_segment_stages(plan, progress, iteration, cancelled, c);
            if (cancelled) break;
            consider(c);
        }
        restore(best.shape, best.states);
        return best.converged;
    }

    // A single frame's start candidates not taken, the start poses whose short fits were put off
    // fitted now, best first by the explained measure.
    std::vector<std::pair<double, FitState>> other_starts() {
        std::vector<std::pair<double, FitState>> alternatives = alternative_starts_;
        double best_cost = std::numeric_limits<double>::infinity(), best_prior = 0;
        for (const auto& [t, found] : deferred_templates_) {
            best_prior = 0;
            short_fits(0, found, &p_.templates().posed()[t].pose, alternatives, best_cost, best_prior);
        }
        std::stable_sort(alternatives.begin(), alternatives.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        return alternatives;
    }

    void restore(const std::vector<double>& shape, const std::vector<FitState>& states) {
        p_.shape() = shape;
        p_.states() = states;
        p_.update_kinematics();
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

    // The extremity start (restarts only, after the templates'): the scan's head, hands and feet (extremities.hpp) in
    // their best labellings; for each, the template placed on the tips, drawn to them by the tip
    // stage, then the short coarse fit on the scan alone. Each result joins `checked`. As a first
    // start too it fixed the same fits, and made standing scans worse (the scan scenario 2.04 ->
    // 2.14 mm: a forearm turned, the fingers off, which tips do not show).
    void extremity_fits(uint32_t f, std::vector<std::pair<double, FitState>>& checked) {
        const ModelTips& tips = p_.templates().tips();
        if (!tips.valid || !p_.has_points(f)) return;
        const std::array<Vector3d, kTipCount>& rest = p_.templates().rest_tips();
        const FrameData& fd = p_.frame(f);
        // At most kExtremityPoints of the scan (its random order): a person's surface is about
        // 3,000 of the graph's cubes, and any cloud costs bounded time. Normals of unknown sign
        // cannot tell surfaces facing each other.
        std::vector<Vector3d> points, normals;
        for (std::size_t i = 0; i < fd.scan_sample.size() && i < kExtremityPoints; ++i) {
            points.push_back(fd.points[fd.scan_sample[i]]);
            if (fd.oriented) normals.push_back(fd.normals[fd.scan_sample[i]]);
        }
        const ScanExtremities ex = scan_extremities(points, normals, kExtremityPicks);
        const std::vector<TipLabelling> labellings = label_extremities(ex, tips, kTipLabellings);
        const Stage coarse = start_stage(std::min(K_, kCoarseComponents));
        for (const TipLabelling& l : labellings) {
            std::vector<SurfacePoint> guides;
            std::vector<Vector3d> targets;
            Eigen::Matrix3Xd src(3, 0), dst(3, 0);
            for (std::size_t t = 0; t < kTipCount; ++t)
                if (l.extremity[t] >= 0) {
                    SurfacePoint sp;
                    sp.vertex[0] = tips.guide[t];
                    guides.push_back(sp);
                    const std::size_t e = std::size_t(l.extremity[t]);
                    targets.push_back(tips.guide[t] == tips.vertex[t] ? ex.points[e] : ex.back_along(e, kPalmBack * l.scale));
                    src.conservativeResize(3, src.cols() + 1), dst.conservativeResize(3, dst.cols() + 1);
                    src.col(src.cols() - 1) = rest[t], dst.col(dst.cols() - 1) = targets.back();
                }
            std::fill(p_.shape().begin(), p_.shape().end(), 0.0);
            p_.states()[f] = p_.placed(f, align_points(src, dst, o_.fit_scale));
            uint32_t iterations = 0;
            bool cancelled = false;
            p_.set_guides(f, guides, targets, kTipSigma);
            p_.run_stage(tip_stage(), f, nullptr, iterations, cancelled);
            p_.clear_guides(f);
            p_.run_stage(coarse, f, nullptr, iterations, cancelled);
            p_.update_kinematics();
            p_.find_pairs(coarse, f);
            const double cost = p_.explained(f);
            checked.emplace_back(cost, p_.states()[f]);
        }
    }

    // The start poses (kStartPoses) placed again with kPlacedAgainSteps rigid steps, each with its
    // short fits, for the restarts. The first placement takes half the rest pose's steps: enough
    // to rank the templates against the rest pose, but on a person folded double (bending forward)
    // its iterations from the principal axes stop 10-20 degrees off and the fit from there ends
    // 140-250 mm off though the template holds the pose (pose library, docs/fitting.md).
    std::vector<std::pair<double, FitState>> placed_again() {
        std::vector<std::pair<double, FitState>> checked;
        RigidStartOptions careful = start_options();
        careful.steps = kPlacedAgainSteps;
        double best_cost = std::numeric_limits<double>::infinity();
        for (const StartTemplate& t : p_.templates().posed()) {
            double best_prior = 0;  // the template's best two
            short_fits(0, rigid_start(t.sample(), p_.cloud_view(0), careful, p_.pool()), &t.pose, checked, best_cost, best_prior);
        }
        return checked;
    }

    // The rigid start search's options for this fit.
    RigidStartOptions start_options() const {
        RigidStartOptions ro;
        ro.fit_scale = o_.fit_scale;
        ro.point_sigma = o_.point_sigma;
        ro.points = std::size_t(0.15 * o_.max_points);
        ro.samples = kExplainedSamples;
        return ro;
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
        const RigidStartOptions ro = start_options();
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
        for (std::size_t t = 0; t < p_.templates().posed().size() && t < kFirstStartPoses; ++t) {
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

    // How the head is turned (head_search.hpp), for every frame with a cloud. Returns whether a
    // head was turned.
    bool search_head() {
        bool turned = false;
        for (uint32_t f = 0; f < F_; ++f)
            if (p_.has_points(f)) turned |= fitting::search_head(p_.kin(f), p_.body(), p_.states()[f], p_.cloud_view(f), p_.vertex_sample(), p_.pool());
        p_.update_kinematics();
        return turned;
    }

    FitProblem p_;
    FitOptions o_;
    uint32_t F_, K_, whole_body_;
    uint32_t searched_frames_ = 0;  // frames started by the cloud start search (with its coarse fit)
    bool given_start_ = false;      // the caller's start (a sequence's tracked frames), not the fit's own
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

namespace {

// Several frames (a capture of one person, or any set of scans of them) from the automatic start.
// Each frame is first fitted alone, with everything a single fit has, then the frames that found
// their person are fitted together from those poses and their median shape with the fine stages
// only (the shared shape's joint refinement; fitted together from the start, frames got no limb
// search nor restarts and ended worse than alone on real scans). Frames of a capture are usually
// in order, and a person moves little between frames: each frame is first started from the last
// good frame's fit (no start search, a fraction of the time), and from the automatic start when
// that fit is judged wrong. A set in no order makes those tracked starts fail: after
// kTrackingMisses of them in a row the automatic start comes first, the last good fit second. A
// frame that still fails is tried from the next good frame's fit; one that fails after all is
// left out of the shared shape and reported (FrameReport::failed, left_out); every other frame is
// returned.
constexpr uint32_t kTrackingMisses = 3;

class Sequence {
public:
    Sequence(const LinearModel& lin, const std::vector<Frame>& frames, const FitOptions& options, const FitProgress& progress,
             const FrameDone& frame_done, ThreadPool* pool)
        : lin_(lin), frames_(frames), options_(options), progress_(progress), frame_done_(frame_done), pool_(pool) {}

    FitSolution run(std::chrono::steady_clock::time_point t0) {
        const std::size_t F = frames_.size();
        fits_.resize(F);
        // First pass, in order: tracked from the last good frame, or the automatic start.
        int64_t last_good = -1;
        uint32_t misses = 0;
        for (std::size_t f = 0; f < F && !cancelled_; ++f) {
            const bool track_first = last_good >= 0 && misses < kTrackingMisses;
            if (track_first) {
                attempt(f, &fits_[std::size_t(last_good)].frames[0]);
                misses = good(f) ? 0 : misses + 1;
            }
            if (!good(f) && !cancelled_) attempt(f, nullptr);
            if (!good(f) && !track_first && last_good >= 0 && !cancelled_) attempt(f, &fits_[std::size_t(last_good)].frames[0]);
            if (good(f)) last_good = int64_t(f);
            if (!cancelled_ && frame_done_ && !frame_done_(uint32_t(f), fits_[f].report.frames[0])) cancelled_ = true;
        }
        // Second pass, backwards: failed frames from the next good frame's fit.
        int64_t next_good = -1;
        for (std::size_t f = F; f-- > 0 && !cancelled_;) {
            if (!fits_[f].frames.empty() && !good(f) && next_good >= 0) {
                attempt(f, &fits_[std::size_t(next_good)].frames[0]);
                if (good(f) && frame_done_ && !frame_done_(uint32_t(f), fits_[f].report.frames[0])) cancelled_ = true;
            }
            if (!fits_[f].frames.empty() && good(f)) next_good = int64_t(f);
        }
        return cancelled_ ? cancelled(t0) : together(t0);
    }

private:
    bool good(std::size_t f) const { return !fits_[f].frames.empty() && !fits_[f].report.frames[0].failed; }

    // Fits frame f alone, from `start` (a fitted state of another frame) or the automatic start,
    // and keeps the result when it is the frame's first, or good where the kept one was not.
    void attempt(std::size_t f, const FitState* start) {
        FitOptions o = options_;
        std::vector<FitState> given;
        if (start) o.auto_start = false, given.push_back(*start);
        const FitProgress each = [&](uint32_t it, double cost) { return !progress_ || progress_(iterations_ + it, cost); };
        Solver alone(lin_, {frames_[f]}, o, pool_);
        FitSolution one = alone.run(start ? &given : nullptr, each, std::chrono::steady_clock::now());
        iterations_ += one.report.iterations;
        restarts_ += one.report.restarts;
        cancelled_ = one.report.cancelled;
        if (fits_[f].frames.empty() || (!one.report.frames[0].failed && !good(f))) fits_[f] = std::move(one);
    }

    // Cancelled: the frames not reached keep the first frame's fit.
    FitSolution cancelled(std::chrono::steady_clock::time_point t0) {
        FitSolution sol;
        for (const FitSolution& one : fits_)
            if (!one.frames.empty() && sol.shape.empty()) sol.shape = one.shape;
        for (const FitSolution& one : fits_) {
            sol.frames.push_back(one.frames.empty() ? fits_[0].frames[0] : one.frames[0]);
            FrameReport fr = one.frames.empty() ? FrameReport{} : one.report.frames[0];
            sol.report.frames.push_back(fr);
        }
        for (auto& st : sol.frames) st.shape = sol.shape;
        sol.report.iterations = iterations_;
        sol.report.restarts = restarts_;
        sol.report.cancelled = true;
        sol.report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return sol;
    }

    // The good frames together from their poses and median shape; failed frames keep their own
    // best pose with the shared shape.
    FitSolution together(std::chrono::steady_clock::time_point t0) {
        const std::size_t F = frames_.size();
        std::vector<std::size_t> kept;
        for (std::size_t f = 0; f < F; ++f)
            if (good(f)) kept.push_back(f);
        FitSolution sol;
        if (kept.empty()) {  // nothing to share: every frame's own best fit, all reported failed
            sol.shape = fits_[0].shape;
            for (const FitSolution& one : fits_) sol.frames.push_back(one.frames[0]), sol.report.frames.push_back(one.report.frames[0]);
        } else {
            std::vector<double> median(fits_[kept[0]].shape.size());
            for (std::size_t k = 0; k < median.size(); ++k) {
                std::vector<double> v;
                for (std::size_t f : kept) v.push_back(fits_[f].shape[k]);
                std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
                median[k] = v[v.size() / 2];
            }
            std::vector<Frame> frames;
            std::vector<FitState> starts;
            for (std::size_t f : kept) {
                frames.push_back(frames_[f]);
                starts.push_back(fits_[f].frames[0]);
                starts.back().shape = median;
            }
            FitOptions joint = options_;
            joint.auto_start = false;
            Solver solver(lin_, frames, joint, pool_);
            const FitProgress rest = [&](uint32_t it, double cost) { return !progress_ || progress_(iterations_ + it, cost); };
            const FitSolution shared = solver.run(&starts, rest, t0, true);
            sol.shape = shared.shape;
            sol.report = shared.report;
            sol.report.frames.clear();
            std::size_t next = 0;
            for (std::size_t f = 0; f < F; ++f) {
                if (next < kept.size() && kept[next] == f) {
                    sol.frames.push_back(shared.frames[next]);
                    sol.report.frames.push_back(shared.report.frames[next]);
                    ++next;
                } else {
                    sol.frames.push_back(fits_[f].frames[0]);
                    sol.report.frames.push_back(fits_[f].report.frames[0]);
                    sol.report.frames.back().left_out = true;
                }
            }
        }
        for (auto& st : sol.frames) st.shape = sol.shape;
        sol.report.iterations += iterations_;
        sol.report.restarts += restarts_;
        sol.report.problem = FitProblemKind::None;
        sol.report.problem_text.clear();
        uint32_t failed = 0;
        for (std::size_t f = 0; f < F; ++f) {
            const FrameReport& fr = sol.report.frames[f];
            if (!fr.failed) continue;
            sol.report.frames[f].failed = true;
            if (failed++ == 0) {
                sol.report.problem = fr.problem;
                sol.report.problem_text = "frame " + std::to_string(f) + ": " + fr.problem_text;
            }
        }
        sol.report.failed_frames = failed;
        sol.report.implausible = failed > 0;
        // Converged: the shared fit converged on the frames kept; failed frames are reported
        // per frame (left out, not counted as converged).
        sol.report.converged = !kept.empty() && sol.report.converged;
        sol.report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return sol;
    }

    const LinearModel& lin_;
    const std::vector<Frame>& frames_;
    const FitOptions& options_;
    const FitProgress& progress_;
    const FrameDone& frame_done_;
    ThreadPool* pool_;
    std::vector<FitSolution> fits_;  // each frame's best single fit so far
    uint32_t iterations_ = 0, restarts_ = 0;
    bool cancelled_ = false;
};

}  // namespace

FitSolution fit(const LinearModel& lin, const std::vector<Frame>& frames, const FitOptions& options,
                const std::vector<FitState>* start, const FitProgress& progress, ThreadPool* pool, const FrameDone& frame_done) {
    validate(lin, frames, options);
    if (start && !options.auto_start)
        SSC_REQUIRE_ARG_S(start->size() == frames.size(), "fit: " << start->size() << " start states for " << frames.size() << " frames");
    // The reported time includes the setup (the scans' grids and k-d trees, normal estimation).
    const auto t0 = std::chrono::steady_clock::now();
    if (frames.size() == 1 || (start && !options.auto_start)) {
        Solver solver(lin, frames, options, pool);
        FitSolution sol = solver.run(start, progress, t0);
        for (const FrameReport& fr : sol.report.frames) sol.report.failed_frames += fr.failed;
        if (frame_done && frames.size() == 1) frame_done(0, sol.report.frames[0]);
        return sol;
    }
    return Sequence(lin, frames, options, progress, frame_done, pool).run(t0);
}

}  // namespace ssc::fitting
