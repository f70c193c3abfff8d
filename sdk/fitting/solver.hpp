// Fitting the model to measurements of one person: landmarks and point clouds (scans, depth
// images turned into points), in one or several frames that share a shape and have a pose each.
//
// The method, and where each part lives (docs/fitting.md tells the longer story):
//   schedule       solver.cpp: the start, the stages, the limb and hand searches, restarts, the
//                  report, and several frames fitted alone and then together;
//   start          landmarks: a rigid alignment with scale (Umeyama); clouds: rigid_start.hpp over
//                  the template at rest and in start poses (start_templates.hpp), the best
//                  candidates given a short coarse fit;
//   stages         stages.hpp: rigid, coarse (trunk and limbs, few components), fine (everything,
//                  half the points), polish (all the points);
//   problem        fit_problem.hpp: the frames' prepared data, the parameters, the posed model;
//   energy         data_term.hpp (landmarks: Huber; clouds: point-to-plane, Geman-McClure,
//                  robust.hpp) and priors.hpp (shape, per-joint rotation, joint-limit walls);
//   correspondences correspondences.hpp: both ways through uniform grids (grid_index.hpp), with
//                  normal and reciprocity tests and trimming; missing normals from scan_normals.hpp;
//   solve          levenberg_marquardt.hpp over the analytic Jacobians of kinematics.hpp, the
//                  normal equations summed in blocks (normal_equations.hpp) into the arrow of shape
//                  and per-frame columns (arrow_system.hpp);
//   searches       limb_search.hpp (raised, bent arms and legs) between the coarse and the fine
//                  stage, hand_search.hpp (closure of each hand) after the fine stage, both scored
//                  by explained.hpp.
#pragma once

#include "common/thread_pool.hpp"
#include "fitting/judgement.hpp"
#include "fitting/kinematics.hpp"
#include "fitting/observations.hpp"

#include <functional>
#include <memory>
#include <vector>

namespace ssc::fitting {

struct FitOptions {
    uint32_t components = 0xFFFFFFFFu;  // shape components used (clamped to the model's)
    bool fit_scale = false;             // solve a global scale too (data in unknown units)
    double landmark_sigma = 0.01;       // metres: expected landmark placement error
    double point_sigma = 0.004;         // metres: expected scan noise plus model error
    double shape_prior = 1;             // multiplies the Gaussian shape prior (0 = none)
    double segment_prior = 1;           // further multiplies it for segment components (LinearModel with segments)
    double pose_prior = 1;              // multiplies the joint rotation prior (0 = none)
    bool joint_limits = true;           // keep joints within their anatomical ranges (joint_limits.hpp)
    uint32_t max_iterations = 60;       // Levenberg-Marquardt iterations, all stages together
    uint32_t max_points = 3000;         // scan points used per iteration (a fixed random subset)
    uint32_t seed = 1;                  // for that subset
    bool auto_start = true;             // false: start from the given state instead
    bool hand_search = true;            // search each hand's closure (open .. fist) in scans (hand_search.hpp)
    // Fitter only: the model's segment shape spaces (head, arms, torso, legs) join the whole body's
    // components when the fit uses all of those (a LinearModel with segments; docs/fitting.md).
    bool segments = true;
    // With segment components: keep them whatever the scan says (registration's model fit, which
    // measured them so); else only when they bring the scan kSegmentsCloser closer (solver.cpp).
    bool keep_segments_always = false;
};

// How one frame's fit was judged (judgement.hpp).
struct FrameReport {
    bool failed = false;  // the frame's fit did not find the person (its problem says why)
    FitProblemKind problem = FitProblemKind::None;
    std::string problem_text;  // one line: what, where, how much; empty without a problem
    std::string unscanned;     // parts of the body the scan does not show (a partial scan), or empty
    double unexplained = 0;    // FitReport::unexplained of this frame
    int32_t joint = -1;        // the joint furthest past its range (-1: none)
    double joint_excess = 0;   // radians it lies past the range
    double off_scan = 0;       // the largest share of a limb or the head on no scan (all-round scans)
    double loose = 0;          // share of the scan over 2.5 cm from the fitted surface
    double coverage = 0;       // the trunk's share near the scan (about 1 all round, 0.5 one view)
    int32_t region = -1;       // BodyRegion off the scan, else the most unscanned one (-1: none)
    bool left_out = false;     // several frames: failed alone, so kept out of the shared shape
};

struct FitReport {
    uint32_t iterations = 0;
    bool converged = false, cancelled = false;
    double initial_cost = 0, final_cost = 0;
    double landmark_rms = 0;   // metres, over all landmarks of all frames
    double point_mean = 0;     // metres, mean distance of accepted scan points to the model surface
    double inlier_fraction = 0;
    double seconds = 0;
    // Fits redone from another start candidate because the one before was judged wrong
    // (judgement.hpp; single-frame fits from the automatic start; see solver.cpp). iterations
    // counts them all.
    uint32_t restarts = 0;
    // Share of the scan points (a fixed sample of each frame's) farther than 5 cm from the fitted
    // surface and on a surface (isolated outliers do not count), the worst frame's: 0 for landmark-only fits. Above 0.1 the fit has not found the
    // person (a limb or the whole body in the wrong place): converged is then false.
    double unexplained = 0;
    // A single frame's fit (any frame's, with several) that is still judged wrong after every
    // restart (judgement.hpp: a joint past its range, the scan unexplained, a limb on no scan): a
    // limb or the body is likely in the wrong place, and converged is false.
    bool implausible = false;
    // The first failed frame's problem, and its description; None / empty when none failed.
    FitProblemKind problem = FitProblemKind::None;
    std::string problem_text;
    std::string unscanned;  // the first frame's parts the scan does not show, or empty
    std::vector<FrameReport> frames;  // one per frame
    uint32_t failed_frames = 0;       // frames whose fit failed (FrameReport::failed)
};

// Called once per iteration; return false to cancel (the best state so far is kept).
using FitProgress = std::function<bool(uint32_t iteration, double cost)>;
// Called when a frame has been fitted (several frames: after its own fit, in order, and again
// when a later try from a neighbour fixes a failed frame; one frame: at the end); return false to
// cancel.
using FrameDone = std::function<bool(uint32_t frame, const FrameReport& report)>;

struct FitSolution {
    std::vector<double> shape;      // components() values; the rest of the model's are zero
    std::vector<FitState> frames;   // per frame: pose, translation, scale (shape copied in)
    FitReport report;
};

// Fits frames to the model. `start` (optional, one per frame) is used when auto_start is false.
// `pool` (optional) lends worker threads (start candidates, correspondences, normal equations, limb
// search); results do not depend on its size. Several frames from the automatic start: each is
// fitted alone (tracked from the last good frame first), failed frames are tried from their
// neighbours' fits and, still failing, left out of the shared shape and reported per frame
// (solver.cpp, Sequence); every frame gets a state.
// Throws ssc::Error on invalid input (no data, NaN, bad indices).
FitSolution fit(const LinearModel& lin, const std::vector<Frame>& frames, const FitOptions& options,
                const std::vector<FitState>* start = nullptr, const FitProgress& progress = {}, ThreadPool* pool = nullptr,
                const FrameDone& frame_done = {});


// The six CAESAR hand landmarks (metacarpal-phalangeal II and V, dactylion, each side): scanned
// subjects often close their hands, so fits commonly leave them out.
bool is_hand_landmark(const std::string& landmark_name);

}  // namespace ssc::fitting
