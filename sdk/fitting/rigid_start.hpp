// The automatic start for a frame with a cloud and no landmarks: the mean body, rigidly placed.
//
// The cloud's longest principal axis is the template's longest axis (the body's up axis at rest);
// its sign and the facing direction are unknown, so 8 candidates (2 up signs x 4 headings about it) each get a few rigid ICP steps and
// are ranked by how well they explain the cloud (explained.hpp). The model side is the mean body
// at rest, which does not change: its k-d tree is built once and each step carries the scan
// points into the model's frame instead of re-posing the model, and the candidates run in
// parallel on the pool (the result does not depend on its size).
#pragma once

#include "common/rigid.hpp"
#include "common/thread_pool.hpp"
#include "fitting/explained.hpp"
#include "fitting/nearest.hpp"

#include <vector>

namespace ssc::fitting {

// The template's sampled vertices in one pose (mean shape: at rest, or a start pose such as
// crouching). All referenced, none owned.
struct RestSample {
    const std::vector<Vector3d>* points = nullptr;   // metres
    const std::vector<Vector3d>* normals = nullptr;  // unit, outward
    const PointIndex* index = nullptr;               // over *points
    Vector3d centre = Vector3d::Zero();              // of the whole surface, metres
    double bottom = 0, top = 0;                      // its extent along frame's second axis, metres
    // The template's principal frame (columns: across, its longest axis, the third): the cloud's
    // principal axes are matched to these. The rest body's is the model frame (x, y up, z).
    Matrix3d frame = Matrix3d::Identity();
};

// How far the start search's correspondences reach (metres): a candidate may start tens of
// centimetres off.
constexpr double kStartReach = 0.5;

struct StartCandidate {
    Similarity placement;  // world = scale * R * rest + t
    double score;          // the explained measure (lower is better)
};

struct RigidStartOptions {
    bool fit_scale = false;       // scale from the cloud's extent along the up axis, and fitted
    double point_sigma = 0.004;   // metres, as FitOptions::point_sigma
    std::size_t points = 450;     // correspondences per direction and step
    int steps = 6;                // Gauss-Newton steps per candidate
    std::size_t samples = 1000;   // points each way the explained measure scores
};

// All candidates, best first. The cloud must have at least 3 points.
std::vector<StartCandidate> rigid_start(const RestSample& rest, const CloudView& cloud, const RigidStartOptions& options,
                                        ThreadPool& pool);

}  // namespace ssc::fitting
