// The fit's correspondences between the posed model and a frame's cloud, found again every
// iteration: scan points to their nearest model point, model vertices to their nearest scan point,
// each within the stage's gate and with agreeing normals, then trimmed.
#pragma once

#include "common/thread_pool.hpp"
#include "fitting/explained.hpp"
#include "fitting/grid_index.hpp"
#include "fitting/kinematics.hpp"

#include <vector>

namespace ssc::fitting {

// One correspondence between the model surface and a measured point.
struct Pair {
    SurfacePoint model;
    Vector3d target, normal;  // normal: unit, or zero for point-to-point only
    double weight;            // confidence
};

// Model-to-scan pairs: how far (a fraction of the gate) the scan point's own nearest model point
// may lie from the vertex.
constexpr double kReciprocal = 0.5;

// The posed model a search reads. All referenced, none owned.
struct PosedModel {
    const std::vector<Vector3d>* vertices = nullptr;  // every vertex (only the sample's need be current when !dense)
    const std::vector<Vector3d>* normals = nullptr;   // unit, the same vertices
    const std::vector<uint32_t>* sample = nullptr;    // the area-uniform vertex sample (model-to-scan queries)
    // Over the posed vertices (dense) or the posed sample (index i is sample[i]): scan-to-model queries.
    const GridIndex* index = nullptr;
    bool dense = false;
};

// What a search may accept (a stage's settings).
struct PairGate {
    double max_distance;    // metres
    double min_normal_dot;  // normals_agree()
    std::size_t scan_points;   // scan points queried (a prefix of the cloud's sample)
    std::size_t model_points;  // model vertices queried (a prefix of the vertex sample)
};

// Appends the trimmed pairs both ways to `out` (scan-to-model first); returns the queries made.
// The cloud's confidence must be given. Queries run on the pool's threads in fixed chunks merged
// in order, and each direction is trimmed on its own: the same pairs for any thread count.
std::size_t find_pairs(const CloudView& cloud, const PosedModel& model, const PairGate& gate, ThreadPool& pool,
                       std::vector<Pair>& out);

}  // namespace ssc::fitting
