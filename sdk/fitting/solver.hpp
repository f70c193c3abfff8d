// Fitting the model to measurements of one person: landmarks and point clouds (scans, depth
// images turned into points), in one or several frames that share a shape and have a pose each.
//
// Method (each choice is explained where it is made in solver.cpp):
//   start   rigid alignment with scale from landmarks (Umeyama) when a frame has any; otherwise
//           from the cloud's principal axes, trying the plausible facing directions
//           (rigid_start.hpp), the best two (two more at a time, up to all eight, while the
//           best ends in an implausible pose) given a short coarse fit;
//   solve   Levenberg-Marquardt over shape, per-joint rotations, translation and optional scale, with
//           the analytic Jacobians of kinematics.hpp;
//   data    landmarks (robust Huber loss), clouds with correspondences both ways (uniform grids,
//           grid_index.hpp: every query has a gate; the start search's far-reaching ones use
//           nanoflann k-d trees), point-to-plane where normals exist, normal-compatibility and
//           distance tests
//           (model-to-scan pairs must agree with the scan point's own nearest model point, so
//           holes do not drag the model), Geman-McClure loss and trimming (robust.hpp);
//   priors  Gaussian on shape (the model's own: coefficients are standard deviations) and on each
//           joint's rotation, and soft walls at the anatomical joint limits (joint_limits.hpp);
//           coarse-to-fine stages (rigid, then trunk and limbs with few components, then
//           everything on half the scan points, then a two-iteration polish on all of them); a
//           frame started by the cloud search skips the rigid stage;
//   limbs   between the coarse and the fine stage, a search over anatomical poses of each arm and
//           leg with clouds (raised overhead, forward, bent elbows and knees; upper and middle
//           joint together, the best refined) that the coarse stage's short-reaching
//           correspondences cannot find from the rest pose (limb_search.hpp, scored by explained.hpp),
//           the limbs before one whose move changed much searched again;
//   hands   after the fine stage, each hand's closure (open .. fist) that explains the scan best
//           (hand_search.hpp); the fingers' prior is then centred on that closure;
//   restart a single frame's fit from the automatic start that ends in an implausible pose is
//           redone from the start search's next candidates (at most two).
#pragma once

#include "common/thread_pool.hpp"
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
    double pose_prior = 1;              // multiplies the joint rotation prior (0 = none)
    bool joint_limits = true;           // keep joints within their anatomical ranges (joint_limits.hpp)
    uint32_t max_iterations = 60;       // Levenberg-Marquardt iterations, all stages together
    uint32_t max_points = 3000;         // scan points used per iteration (a fixed random subset)
    uint32_t seed = 1;                  // for that subset
    bool auto_start = true;             // false: start from the given state instead
    bool hand_search = true;            // search each hand's closure (open .. fist) in scans (hand_search.hpp)
};

struct FitReport {
    uint32_t iterations = 0;
    bool converged = false, cancelled = false;
    double initial_cost = 0, final_cost = 0;
    double landmark_rms = 0;   // metres, over all landmarks of all frames
    double point_mean = 0;     // metres, mean distance of accepted scan points to the model surface
    double inlier_fraction = 0;
    double seconds = 0;
    // Fits redone from another start candidate because the one before ended implausible
    // (single-frame fits from the automatic start; see solver.cpp). iterations counts them all.
    uint32_t restarts = 0;
    // Share of the scan points (a fixed sample of each frame's) farther than 5 cm from the fitted
    // surface and on a surface (isolated outliers do not count), the worst frame's: 0 for landmark-only fits. Above 0.1 the fit has not found the
    // person (a limb or the whole body in the wrong place): converged is then false.
    double unexplained = 0;
    // A single frame's fit (any frame's, with several) that still ends in an implausible pose or
    // leaves more than 3 % of its scan unexplained after every restart: a limb or the body is
    // likely in the wrong place, and converged is false.
    bool implausible = false;
};

// Called once per iteration; return false to cancel (the best state so far is kept).
using FitProgress = std::function<bool(uint32_t iteration, double cost)>;

struct FitSolution {
    std::vector<double> shape;      // components() values; the rest of the model's are zero
    std::vector<FitState> frames;   // per frame: pose, translation, scale (shape copied in)
    FitReport report;
};

// Fits frames to the model. `start` (optional, one per frame) is used when auto_start is false.
// `pool` (optional) lends worker threads (start candidates, correspondences, normal equations, limb
// search); results do not depend on its size.
// Throws ssc::Error on invalid input (no data, NaN, bad indices).
FitSolution fit(const LinearModel& lin, const std::vector<Frame>& frames, const FitOptions& options,
                const std::vector<FitState>* start = nullptr, const FitProgress& progress = {}, ThreadPool* pool = nullptr);


// The six CAESAR hand landmarks (metacarpal-phalangeal II and V, dactylion, each side): scanned
// subjects often close their hands, so fits commonly leave them out.
bool is_hand_landmark(const std::string& landmark_name);

}  // namespace ssc::fitting
