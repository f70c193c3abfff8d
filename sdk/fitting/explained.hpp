// How well a posed model explains a cloud: the measure that chooses between start candidates and
// between limb poses (solver.cpp). Unlike the fit's cost, which gates correspondences away, it
// counts both ways over fixed point samples with truncated squared distances, so a candidate
// cannot look good by leaving data unexplained.
#pragma once

#include "fitting/grid_index.hpp"
#include "fitting/kinematics.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace ssc::fitting {

// What the measure reads of one frame's cloud. All referenced, none owned.
struct CloudView {
    const std::vector<Vector3d>* points = nullptr;
    const std::vector<Vector3d>* normals = nullptr;  // zero where unknown
    bool oriented = true;                            // normals carry their sign
    const GridIndex* grid = nullptr;                 // over *points, for queries within a radius
    // Over *points with cells a few times larger and empty space indexed far out: for the start
    // search's far-reaching queries (kStartReach), which the fine grid would answer shell by shell.
    const GridIndex* coarse_grid = nullptr;
    const std::vector<uint32_t>* sample = nullptr;   // random order of the points; a prefix is scored
    const std::vector<double>* confidence = nullptr; // per point in [0, 1]; null: all 1
};

// Whether a scan normal (zero: unknown) and a model normal agree to within min_dot (a cosine);
// unoriented scan normals are compared up to their sign. The one rule of the fit's
// correspondences, the start search's and the explained measure (min_dot 0).
inline bool normals_agree(const Vector3d& scan_n, const Vector3d& model_n, bool oriented, double min_dot) {
    if (scan_n.squaredNorm() == 0) return true;
    const double dot = scan_n.dot(model_n);
    return (oriented ? dot : std::abs(dot)) >= min_dot;
}

// The term of scan point i against a model point x with unit normal n: the squared distance,
// capped at cap2; a pair whose normals face away from each other counts as unexplained (cap2).
double explained_term(const CloudView& cloud, uint32_t i, const Vector3d& x, const Vector3d& n, double cap2);

// The term of a model point x with unit normal n against its nearest scan point: the same cap,
// and cap^2 when no scan point lies within the cap.
double model_term(const CloudView& cloud, const Vector3d& x, const Vector3d& n, double cap);

// Cap of the measure for whole-body placements (start candidates), metres: a candidate still in
// the rest pose has limbs off by more, which simply count as unexplained.
constexpr double kPlacementCap = 0.05;

// The measure of a posed model sample: points and unit normals, the first `samples` of them
// scored against the cloud; nearest_model(p) gives the sample point nearest to p (or
// GridIndex::kNone when none is within the cap), for the first `samples` of the cloud's sample. Both the start search (rest body, scan carried into its frame)
// and the fitter (posed sample) score placements with it.
double explained_measure(const CloudView& cloud, const std::vector<Vector3d>& points, const std::vector<Vector3d>& normals,
                         const std::function<uint32_t(const Vector3d&)>& nearest_model, double cap, std::size_t samples);

// The measure for poses of one limb (a joint and everything below it), re-posing only the
// sampled model vertices the limb moves (about a sixth): the terms of the fixed rest are found
// once, at construction. Scan points the fixed vertices already explain to within 1 cm count as
// constant. Normals of moved vertices are the construction-time ones carried by the change of
// their skinning rotation. Not thread-safe (scratch buffers).
class LimbScore {
public:
    // kin: updated to the current state, whose posed vertices and normals are given (every model
    // vertex). vertices: the model vertex sample (area-uniform); the first `samples` of it and of
    // the cloud's sample are scored. cap: metres, for scan points; model_cap for model vertices,
    // smaller because scans have holes: a limb lying in a hole is weak evidence against it,
    // while every scan point should be explained.
    LimbScore(const Kinematics& kin, const CloudView& cloud, const std::vector<uint32_t>& vertices,
              const std::vector<Vector3d>& posed, const std::vector<Vector3d>& posed_normals, uint32_t joint, double cap,
              double model_cap, std::size_t samples);

    // The measure with kin updated to a candidate state (only the limb's joints differing). Every
    // term is non-negative, so once the sum reaches `bound` the candidate cannot beat a measure of
    // `bound`: the scoring stops there and returns a value >= bound (not the measure).
    double operator()(const Kinematics& kin, double bound = std::numeric_limits<double>::infinity());

private:
    CloudView cloud_;
    double cap2_, model_cap_;
    std::vector<uint32_t> moving_;          // model vertices the limb moves
    struct Influence {
        uint16_t joint[4];
        double weight[4];  // 0 for unused slots
    };
    std::vector<Influence> influence_;     // each moving vertex's skinning
    std::vector<uint8_t> moving_scored_;    // whether each is among the model-to-scan samples
    std::vector<Vector3d> unposed_, rest_normal_;
    std::vector<uint32_t> open_;            // scan points not settled by the fixed vertices
    std::vector<double> fixed_d2_, fixed_term_;  // each one's nearest fixed vertex: distance^2, term
    double fixed_sum_ = 0;                  // settled scan points and the fixed vertices' terms
    std::vector<Vector3d> posed_, normals_;  // scratch
    GridIndex moved_index_{0.04};            // over posed_ (the sample's spacing is about 2.5 cm)
};

}  // namespace ssc::fitting
