// A fit of the model to one person: the observations, frame by frame, and after solve() the
// solution, the fitted surfaces and each scan point's residual. What ssc_fitter wraps, as ssc_body
// wraps Body; the work is fit() (solver.hpp).
#pragma once

#include "common/thread_pool.hpp"
#include "fitting/depth_image.hpp"
#include "fitting/observations.hpp"
#include "fitting/solver.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace ssc::fitting {

class Fitter {
public:
    // options.components: 0 or more than the model has are refused (Error, INVALID_ARGUMENT), as
    // are options fit() refuses. The model must outlive the fitter. anatomy: the model's, shared
    // (null: derived here).
    Fitter(const Model& model, const FitOptions& options, std::shared_ptr<const anatomy::ModelAnatomy> anatomy = nullptr);

    const Model& model() const { return linear_.model; }
    const FitOptions& options() const { return options_; }

    // Observations join frame `frame`: an existing one, or frame_count() to start the next. Each is
    // checked whole (observations.hpp) before anything is added; adding forgets the solution.
    uint32_t frame_count() const { return uint32_t(frames_.size()); }
    void add_landmarks(uint32_t frame, const std::vector<LandmarkTarget>& targets);
    void add_cloud(uint32_t frame, PointCloud cloud);  // at least 16 points
    uint32_t add_depth_image(uint32_t frame, const DepthView& image);  // returns the points it gave
    uint32_t point_count(uint32_t frame) const;  // 0 for a frame that does not exist
    // A frame's observations as added (metres; depth images as the points they gave). Error
    // (INVALID_ARGUMENT) for a frame that does not exist.
    const Frame& frame(uint32_t frame) const;
    void clear();  // every frame and the solution

    // Fits every frame (fit()). A cancelled fit (progress returned false) keeps the best state so
    // far as the solution, with report.cancelled set.
    // frame_done: see fit().
    const FitReport& solve(const FitProgress& progress = {}, ThreadPool* pool = nullptr, const FrameDone& frame_done = {});

    // After a solve (else Error, INVALID_ARGUMENT): the solution, one frame's state, its posed
    // vertices, and per scan point of the frame (in the order added) the distance to the fitted
    // surface along the nearest vertex's normal, metres.
    bool solved() const { return solved_; }
    const FitSolution& solution() const;
    const FitState& frame_state(uint32_t frame) const;
    std::vector<Vector3d> vertices(uint32_t frame) const;
    const std::vector<float>& point_residuals(uint32_t frame) const;

private:
    Frame& frame_for_adding(uint32_t frame);

    FitOptions options_;
    LinearModel linear_;
    std::vector<Frame> frames_;
    bool solved_ = false;
    FitSolution solution_;
    std::vector<std::vector<float>> residuals_;  // per frame, per point
};

}  // namespace ssc::fitting
