#include "fitting/stages.hpp"

#include <algorithm>

namespace ssc::fitting {

namespace {
// Iterations of the polish stage.
constexpr uint32_t kPolishIterations = 2;
}  // namespace

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

// The fine stage's first steps (shape components 11 to 50 joining, the wrists and fingers free)
// need no more than half the points, and the last steps get the full accuracy. Against the whole
// fine stage on all points (benchmark, 30 trials): a tenth less CPU time, mean errors up to 0.2 mm
// higher (scan 2.18 against 2.04 mm).
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

Stage start_stage(uint32_t components) {
    Stage s{};
    s.iterations = 8;
    s.body_joints = true;
    s.all_joints = false;
    s.components = components;
    s.max_distance = 0.15;
    s.gm_scale = 8.0;
    s.min_normal_dot = 0.0;
    s.point_fraction = 0.25;
    return s;
}

Stage tip_stage() {
    Stage s{};
    s.iterations = 12;
    s.body_joints = true;
    s.all_joints = false;
    s.components = 0;
    s.max_distance = 0;
    s.gm_scale = 8.0;
    s.min_normal_dot = 0.0;
    s.point_fraction = 0;
    s.tolerance = 1e-4;
    return s;
}

// The tip stage's inverse kinematics, drawn to landmarks instead of tips, with the coarse stage's
// shape components.
Stage landmark_stage() {
    Stage s = tip_stage();
    s.iterations = 10;
    s.components = kCoarseComponents;
    return s;
}

Schedule schedule(uint32_t max_iterations, uint32_t components, bool given_start, uint32_t whole_body) {
    const uint32_t total = std::max<uint32_t>(max_iterations, 3);
    const uint32_t rigid = std::max<uint32_t>(1, total / 5), coarse = std::max<uint32_t>(1, total / 3);
    const uint32_t later = total - rigid - coarse;  // at least 1: the fine stage keeps one
    const uint32_t fine = later - std::min(kPolishIterations, later - 1);
    if (whole_body < components && fine >= 2)
        return Schedule{{rigid_stage(rigid, given_start), coarse_stage(coarse, std::min(whole_body, kCoarseComponents)),
                         fine_stage(fine - fine / 2, whole_body, false), fine_stage(later - fine, components, true)},
                        fine / 2};
    return Schedule{{rigid_stage(rigid, given_start), coarse_stage(coarse, std::min(components, kCoarseComponents)),
                     fine_stage(fine, components, false), fine_stage(later - fine, components, true)}};
}

}  // namespace ssc::fitting
