// The coarse-to-fine stages of a fit: what each moves, how far its correspondences reach and how
// robust its loss is. Each stage is a function so that its settings have names; the schedule that
// runs them is in solver.cpp, the reasons behind the numbers in docs/fitting.md.
#pragma once

#include <cstdint>

namespace ssc::fitting {

// Iterations in a row without a relative gain of kPlateau that end a stage (Stage::stall; see
// levenberg_marquardt.hpp).
constexpr uint32_t kStall = 3;

struct Stage {
    uint32_t iterations;
    bool body_joints, all_joints;  // rigid only when both are false
    uint32_t components;
    double max_distance;  // metres, correspondence gate
    double gm_scale;      // Geman-McClure scale in sigmas
    double min_normal_dot;
    double point_fraction;  // of FitOptions::max_points; 0: no scan points (landmarks and guides only)
    double tolerance = 1e-5;  // converged when a step lowers the cost by less than this fraction
    // Scan-to-model correspondences against every vertex, or (coarse stages) against the
    // area-sampled subset only: a tree a quarter the size, and coarse steps need no more.
    bool dense_model = false;
    // Iterations in a row without a gain of kPlateau that end the stage. The fine stage starts
    // close, with dense and steady correspondences: a third such iteration there did not change
    // the benchmark's errors and cost a tenth of the fit's time.
    uint32_t stall = kStall;
};

// Rigid: translation, rotation (and scale) only. A given start may be off by tens of centimetres
// at the head: the stage then reaches far with a wide loss; after the automatic start search it
// stays close.
Stage rigid_stage(uint32_t iterations, bool given_start);

// Coarse: the trunk and limbs (the joints whose role says so, anatomy/joint_roles.hpp) and the
// first few shape components.
Stage coarse_stage(uint32_t iterations, uint32_t components);

// Fine: every joint and component, dense correspondences, on half the points until the first
// iteration without a gain; polish: the same on all of them for a fixed budget.
Stage fine_stage(uint32_t iterations, uint32_t components, bool polish);

// The short coarse fit each start candidate gets (solver.cpp, short_fits): a little farther and
// more robust than the coarse stage, on a quarter of the points.
Stage start_stage(uint32_t components);

// A frame with landmarks, after their rigid alignment: the trunk and limbs and the first shape
// components drawn to the landmarks alone (no scan points), inverse kinematics under the pose
// prior, so the scan's correspondences start from the person's pose rather than the rest pose.
Stage landmark_stage();

// The extremity start's first step (solver.cpp): the trunk and limbs drawn to the scan's head,
// hands and feet alone (guides, no scan points): inverse kinematics under the pose prior.
Stage tip_stage();

// Shape components the coarse stages fit.
constexpr uint32_t kCoarseComponents = 10;

// The four stages of a fit (rigid, coarse, fine, polish) sharing a budget of iterations: a fifth
// rigid, a third coarse, two (when there is room) the polish, the rest fine.
struct Schedule {
    Stage stages[4];
    // With segment components: the fine stage fits the whole body's alone, then (once the pose has
    // settled and a failed fit has been restarted, solver.cpp) this many more iterations of it with
    // every component, then the polish.
    uint32_t segment_iterations = 0;
    static constexpr int kRigid = 0, kCoarse = 1, kFine = 2, kPolish = 3;
};
// whole_body < components: the components from whole_body on (a LinearModel's segments) join for
// the fine stage's second half (segment_iterations).
Schedule schedule(uint32_t max_iterations, uint32_t components, bool given_start, uint32_t whole_body);

}  // namespace ssc::fitting
