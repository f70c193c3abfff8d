// One fit's problem: the prepared observations of each frame, the parameters being solved for (the
// shared shape and each frame's pose), the posed model, and the energy over them (data_term.hpp,
// priors.hpp) with its correspondences (correspondences.hpp). The schedule (solver.cpp) moves
// the parameters through stages; this evaluates them.
//
// Parameters of all frames form one vector: the shared shape first, then each frame's rotations,
// translation and log scale (kinematics.hpp's layout after the shape).
#pragma once

#include "common/rigid.hpp"
#include "common/thread_pool.hpp"
#include "fitting/correspondences.hpp"
#include "fitting/data_term.hpp"
#include "fitting/explained.hpp"
#include "fitting/grid_index.hpp"
#include "fitting/interpenetration.hpp"
#include "fitting/levenberg_marquardt.hpp"
#include "fitting/nearest.hpp"
#include "fitting/observations.hpp"
#include "fitting/priors.hpp"
#include "fitting/solver.hpp"
#include "fitting/stages.hpp"
#include "fitting/start_templates.hpp"
#include "synthesis/body.hpp"

#include <memory>
#include <random>
#include <vector>

namespace ssc::fitting {

// A stage, correspondence search or evaluation over every frame rather than one (frame_only).
constexpr uint32_t kAllFrames = 0xFFFFFFFFu;

// Scan points and model points the explained measure scores (each a fixed random sample).
constexpr std::size_t kExplainedSamples = 1000;

// One frame's observations, prepared for the fit.
struct FrameData {
    std::vector<SurfacePoint> landmark_points;
    std::vector<Vector3d> landmark_targets;
    std::vector<double> landmark_weights;
    std::size_t own_landmarks = 0;           // the frame's landmarks; guides follow them
    std::vector<Vector3d> points, normals;  // all clouds merged; normals zero where unknown
    std::vector<double> confidence;
    bool oriented = true;                    // normals known with their sign
    GridIndex scan_grid{0.02};               // for the fit's queries (all within a gate or a cap)
    GridIndex start_grid{0.05};              // for the start search's (CloudView::coarse_grid); built when needed
    std::unique_ptr<PointIndex> scan_index;  // for normal estimation and the surface test; built when needed
    std::vector<uint32_t> scan_sample;       // random order of scan points; a prefix is used
    std::vector<Pair> pairs;                 // the current correspondences
};

class FitProblem {
public:
    // Prepares the frames (validated by the caller): merged clouds, their grids, missing normals,
    // the random scan order and the model's vertex sample (both from options.seed).
    FitProblem(const LinearModel& lin, const std::vector<Frame>& frames, const FitOptions& options, ThreadPool* pool);

    const LinearModel& linear() const { return lin_; }
    const FitOptions& options() const { return o_; }
    uint32_t frame_count() const { return F_; }
    uint32_t components() const { return K_; }
    const FrameData& frame(uint32_t f) const { return frames_[f]; }
    bool has_points(uint32_t f) const { return !frames_[f].points.empty(); }
    ThreadPool& pool() { return *pool_; }
    Body& body() { return body_; }
    StartTemplates& templates() { return templates_; }
    const std::vector<uint32_t>& vertex_sample() const { return vertex_sample_; }

    // The parameters. After changing them, update_kinematics() before reading kin().
    std::vector<double>& shape() { return shape_; }
    std::vector<FitState>& states() { return states_; }
    Kinematics& kin(uint32_t f) { return kin_[f]; }
    // Copies the shape into every frame's state and updates the kinematics; derivatives = false
    // for cost-only evaluations, which need no Jacobians.
    void update_kinematics(bool derivatives = true);

    // Levenberg-Marquardt iterations of one stage (all frames, or frame_only). Returns whether it
    // converged; see levenberg_marquardt().
    bool run_stage(const Stage& st, uint32_t frame_only, const LmProgress* progress, uint32_t& iteration, bool& cancelled,
                   double* first_cost = nullptr);

    // Correspondences of every frame (or frame_only) for the current state under a stage's rules.
    void find_pairs(const Stage& st, uint32_t frame_only = kAllFrames);
    // Cost of the current state with the current correspondences; with H and g, the normal
    // equations of its linearisation. frame_only < frame_count() restricts the data to one frame.
    double evaluate(const Stage& st, ArrowSystem* H, Eigen::VectorXd* g, uint32_t frame_only = kAllFrames);
    // The pose prior and limit walls of frame f alone (kinematics current).
    double pose_priors(uint32_t f) const { return pose_prior_.evaluate(kin_[f], states_[f], f * B_, nullptr, nullptr); }
    // Correspondence queries made by the last find_pairs, over its frames.
    std::size_t pair_queries() const;

    // How badly frame f's current state explains its cloud, for choosing between start
    // candidates (explained.hpp).
    double explained(uint32_t f);
    // The share of frame f's scan sample farther than 5 cm from the posed model and on a surface:
    // data the fit does not explain. 0 for a frame without points.
    double unexplained_share(uint32_t f);
    // The share of frame f's scan sample farther than `distance` from the posed model (every
    // vertex, or the vertex sample) and on a surface; unexplained_share is 5 cm from the sample.
    double share_beyond(uint32_t f, double distance, bool every_vertex = true);
    // The mean distance of frame f's scan points to the nearest posed vertex (every vertex), each
    // capped at `cap` metres: how closely the fit lies on the scan, to compare two fits of it.
    double mean_scan_distance(uint32_t f, double cap);
    // The same along the nearest vertex's normal (point to plane): the vertices' spacing (about
    // 1 cm) does not bury a surface that moved a few millimetres.
    double mean_scan_plane_distance(uint32_t f, double cap);
    // The share of frame f's scan points farther than `distance` from the fit along the nearest
    // posed vertex's normal (every vertex; none within `cap` counts as farther): how much of the
    // scan a fit leaves a little way off, tighter than the judgement's loose share.
    double share_beyond_plane(uint32_t f, double distance, double cap);
    // The same counted by the region of each point's nearest vertex (judgement.hpp's regions,
    // vertex_regions(): `regions[v]` below `region_count`): each region's far points over the
    // points nearest it.
    std::vector<double> region_shares_beyond_plane(uint32_t f, double distance, double cap, const std::vector<uint8_t>& regions,
                                                   std::size_t region_count);
    // The same shares into share[region_count], and of each region's far points the share on the
    // side of the surface fewer of them lie into lesser_side[region_count] (0: all in front, or all
    // behind, as on a bump); the count of points nearest each region into near_count when given.
    void region_sides_beyond_plane(uint32_t f, double distance, double cap, const std::vector<uint8_t>& regions, double* share,
                                   double* lesser_side, std::size_t region_count, double* near_count = nullptr);
    // Frame f's posed vertex sample (vertex_sample() order) and each sample's body region
    // (judgement.hpp), for judging a fit.
    const std::vector<Vector3d>& posed_sample(uint32_t f);
    const std::vector<uint8_t>& sample_regions();
    // Every model vertex's body region (judgement.hpp's vertex_regions()), built when needed.
    const std::vector<uint8_t>& vertex_regions();
    // Every model vertex's part (judgement.hpp's vertex_parts(): the regions and the hands).
    const std::vector<uint8_t>& vertex_parts();
    // How far frame f's posed surface passes through itself (interpenetration.hpp).
    LimbsInside limbs_inside(uint32_t f);

    // The template placed by a similarity (world = scale R u + t for its points u), in `pose`
    // (default the rest pose): a root rotation about the root joint plus translation.
    FitState placed(uint32_t f, const Similarity& T, const std::vector<Eigen::Quaterniond>* pose = nullptr);

    // Targets that draw model points like landmarks for a while (the extremity start's tips, drawn
    // at sigma `sigma`, metres), after frame f's own landmarks until clear_guides(f).
    void set_guides(uint32_t f, const std::vector<SurfacePoint>& points, const std::vector<Vector3d>& targets, double sigma);
    void clear_guides(uint32_t f);

    // What the start search, limb and hand searches read of frame f's cloud. The start grid is
    // built by build_start_grid(f) first.
    CloudView cloud_view(uint32_t f) const;
    void build_start_grid(uint32_t f);

private:
    class StageProblem;

    void sample_vertices(std::mt19937& rng);
    void estimate_missing_normals(FrameData& fd);
    void pose_frame(uint32_t f, bool every_vertex);
    double scan_distance_to_fit(uint32_t f, double cap, bool along_normal);
    template <class Visit>
    std::size_t visit_scan_nearest(uint32_t f, double cap, Visit&& visit);
    void find_frame_pairs(uint32_t f, const Stage& st);
    const std::vector<Vector3d>& posed_subset();
    bool active(const Stage& st, uint32_t local) const;
    std::vector<int> solve_columns(const Stage& st) const;
    void apply(const Eigen::VectorXd& delta);

    const LinearModel& lin_;
    FitOptions o_;
    uint32_t F_, K_, B_;
    std::vector<FrameData> frames_;
    std::vector<Kinematics> kin_;
    std::vector<double> shape_;
    std::vector<FitState> states_;
    std::vector<uint8_t> sample_regions_;  // judgement.hpp's region of each, built when needed
    std::vector<uint8_t> vertex_regions_;  // the same for every vertex
    std::vector<uint8_t> vertex_parts_;    // the same with the hands apart
    std::unique_ptr<InterpenetrationTest> inside_test_;  // built when needed
    std::vector<uint32_t> vertex_sample_;  // area-uniform model vertices (model-to-scan, explained measure)
    std::vector<Vector3d> posed_, posed_normals_, subset_posed_, subset_normals_;
    // Over the posed model, rebuilt for each use: every vertex (spacing about 1 cm) or the sample
    // (about 2.5 cm).
    GridIndex dense_grid_{0.02}, sample_grid_{0.04};
    Body body_;
    ThreadPool inline_pool_{1};  // when the caller gives none
    ThreadPool* pool_;
    StartTemplates templates_;
    std::vector<std::size_t> pair_queries_;  // per frame, in the last find_pairs
    PosePrior pose_prior_;
    DataTerm data_;
    // Bumped whenever some frame's pairs change; the data term's blocks were made for this
    // version and frame selection.
    uint64_t pairs_version_ = 0, blocks_pairs_ = ~uint64_t(0);
    uint32_t blocks_frame_ = 0;
};

}  // namespace ssc::fitting
