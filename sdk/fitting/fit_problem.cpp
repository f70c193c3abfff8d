#include "fitting/fit_problem.hpp"

#include "fitting/judgement.hpp"
#include "fitting/posed_surface.hpp"
#include "fitting/scan_normals.hpp"
#include "synthesis/shape_range.hpp"

#include <algorithm>

namespace ssc::fitting {

namespace {

using Eigen::VectorXd;

// Empty shells of cells the scan grid records around each cell (GridIndex::index_empty_space):
// 8 cm: the limb search's model cap and the fine stage's gate (wider queries still skip these).
constexpr int kEmptyShells = 4;

// The start search's grid over a scan: 5 cm cells (FrameData::start_grid), empty space indexed
// out to kStartReach. A query far from the scan then starts at the shell of its nearest points (a
// k-d tree over the scan, which served these queries before, took 9 ms to build on one thread).
constexpr double kStartCell = 0.05;
constexpr int kStartShells = int(kStartReach / kStartCell) + 1;

// A scan point farther than this from the fitted model is unexplained (unexplained_share()).
constexpr double kUnexplainedDistance = 0.05;
// An unexplained point counts when it lies on a surface: this many other scan points within this
// radius (metres). A body scan of 20,000 points has about 30 within 3 cm of each point, one of 6,000
// about 9; uniform clutter around a body (1 to 8 % of the points) has almost none.
constexpr std::size_t kSurfaceNeighbours = 3;
constexpr double kSurfaceRadius = 0.03;

// The k-d tree over a frame's cloud, for normal estimation's and the surface test's queries.
void build_scan_tree(FrameData& fd) {
    if (!fd.scan_index) fd.scan_index = std::make_unique<PointIndex>(fd.points);
}

}  // namespace

// The problem of one stage as the Levenberg-Marquardt core sees it.
class FitProblem::StageProblem final : public LeastSquaresProblem {
public:
    StageProblem(FitProblem& p, const Stage& st, uint32_t frame_only) : p_(p), st_(st), frame_only_(frame_only) {}
    double linearize(ArrowSystem& H, VectorXd& g) override {
        p_.update_kinematics();
        p_.find_pairs(st_, frame_only_);
        return p_.evaluate(st_, &H, &g, frame_only_);
    }
    std::vector<int> step_columns() const override { return p_.solve_columns(st_); }
    void save() override {
        shape_ = p_.shape_;
        states_ = p_.states_;
    }
    void restore() override {
        p_.shape_ = shape_;
        p_.states_ = states_;
    }
    double try_step(const VectorXd& delta) override {
        p_.apply(delta);
        p_.update_kinematics(false);
        return p_.evaluate(st_, nullptr, nullptr, frame_only_);
    }

private:
    FitProblem& p_;
    const Stage& st_;
    uint32_t frame_only_;
    std::vector<double> shape_;
    std::vector<FitState> states_;
};

FitProblem::FitProblem(const LinearModel& lin, const std::vector<Frame>& frames, const FitOptions& o, ThreadPool* pool)
    : lin_(lin), o_(o), F_(uint32_t(frames.size())), K_(lin.K), B_(3 * lin.J + 4), body_(lin.model, nullptr),
      pool_(pool ? pool : &inline_pool_), templates_(lin, body_, vertex_sample_), pose_prior_(lin, o.pose_prior, o.joint_limits),
      data_(K_, B_, F_, lin.V) {
    const auto& d = lin.model.data();
    body_.set_pool(pool_);
    std::mt19937 rng(o.seed);
    frames_.resize(F_);
    for (uint32_t f = 0; f < F_; ++f) {
        auto& fd = frames_[f];
        for (const auto& l : frames[f].landmarks) {
            fd.landmark_points.push_back(landmark_point(d, l.landmark));
            fd.landmark_targets.push_back(l.position);
            fd.landmark_weights.push_back(l.weight);
        }
        fd.own_landmarks = fd.landmark_points.size();
        for (const auto& c : frames[f].clouds) {
            for (std::size_t i = 0; i < c.points.size(); ++i) {
                fd.points.push_back(c.points[i]);
                fd.normals.push_back(c.normals.empty() ? Vector3d::Zero() : c.normals[i]);
                fd.confidence.push_back(c.confidence.empty() ? 1.0 : c.confidence[i]);
            }
        }
        if (!fd.points.empty()) {
            fd.scan_grid.build(fd.points);
            fd.scan_grid.index_empty_space(kEmptyShells, *pool_);
            estimate_missing_normals(fd);
            fd.scan_sample.resize(fd.points.size());
            for (uint32_t i = 0; i < fd.scan_sample.size(); ++i) fd.scan_sample[i] = i;
            std::shuffle(fd.scan_sample.begin(), fd.scan_sample.end(), rng);
        }
        kin_.emplace_back(lin);
    }
    bool any_points = false;
    for (const auto& fd : frames_) any_points |= !fd.points.empty();
    if (any_points) sample_vertices(rng);
    posed_.resize(lin.V);
    posed_normals_.resize(lin.V);
    shape_.assign(K_, 0.0);
    states_.assign(F_, kin_[0].zero_state());
}

// Model vertices for the model-to-scan direction, drawn by surface area (uniform over the
// surface, as scans are), so the finely meshed hands and face are not oversampled.
void FitProblem::sample_vertices(std::mt19937& rng) {
    const auto& d = lin_.model.data();
    std::vector<double> area(lin_.V, 0.0);
    const auto& tri = d.mesh.triangles;
    auto mean = [&](uint32_t v) { return Vector3d(d.shape.mean[3 * v], d.shape.mean[3 * v + 1], d.shape.mean[3 * v + 2]); };
    for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
        const double a = 0.5 * (mean(tri[t + 1]) - mean(tri[t])).cross(mean(tri[t + 2]) - mean(tri[t])).norm();
        for (int i = 0; i < 3; ++i) area[tri[t + i]] += a / 3;
    }
    std::discrete_distribution<uint32_t> pick(area.begin(), area.end());
    std::vector<uint8_t> taken(lin_.V, 0);
    for (uint32_t n = 0; n < 4 * o_.max_points && vertex_sample_.size() < o_.max_points; ++n) {
        const uint32_t v = pick(rng);
        if (!taken[v]) taken[v] = 1, vertex_sample_.push_back(v);
    }
}

// Normals the input did not give (zero) estimated from the neighbouring points.
void FitProblem::estimate_missing_normals(FrameData& fd) {
    bool missing = false;
    for (const auto& n : fd.normals) missing = missing || n.squaredNorm() == 0;
    if (!missing) return;
    build_scan_tree(fd);
    fd.oriented = fitting::estimate_missing_normals(fd.points, *fd.scan_index, fd.normals);
}

void FitProblem::build_start_grid(uint32_t f) {
    FrameData& fd = frames_[f];
    fd.start_grid.build(fd.points);
    fd.start_grid.index_empty_space(kStartShells, *pool_);
}

CloudView FitProblem::cloud_view(uint32_t f) const {
    const FrameData& fd = frames_[f];
    CloudView c;
    c.confidence = &fd.confidence;
    c.points = &fd.points;
    c.normals = &fd.normals;
    c.oriented = fd.oriented;
    c.grid = &fd.scan_grid;
    c.coarse_grid = &fd.start_grid;
    c.sample = &fd.scan_sample;
    return c;
}

void FitProblem::update_kinematics(bool derivatives) {
    for (uint32_t f = 0; f < F_; ++f) {
        states_[f].shape = shape_;
        kin_[f].update(states_[f], derivatives);
    }
}

bool FitProblem::run_stage(const Stage& st, uint32_t frame_only, const LmProgress* progress, uint32_t& iteration, bool& cancelled,
                           double* first_cost) {
    StageProblem problem(*this, st, frame_only);
    return levenberg_marquardt(problem, {st.iterations, st.tolerance, st.stall}, progress, iteration, cancelled, first_cost, *pool_);
}

FitState FitProblem::placed(uint32_t f, const Similarity& T, const std::vector<Eigen::Quaterniond>* pose) {
    FitState s = kin_[f].zero_state();
    kin_[f].update(s);
    const Vector3d root = kin_[f].joint_position(0);
    if (pose) s.pose = *pose;
    const Matrix3d R0 = lin_.rest_orient[0];
    s.pose[0] = (Eigen::Quaterniond(R0.transpose() * T.R * R0) * s.pose[0]).normalized();
    s.scale = T.scale;
    s.translation = T.t + T.scale * T.R * root - T.scale * root;
    return s;
}

// Posed vertices and normals of frame f: every vertex (the synthesis kernels), or only the vertex
// sample, posed by kin_[f] (which must be current) with its rest normals carried by the skinning
// rotation. The sample is a quarter of the vertices and needs no normals pass: enough for the
// coarse stages and the explained measure, which use the sample only.
void FitProblem::pose_frame(uint32_t f, bool every_vertex) {
    if (every_vertex) {
        posed_surface(body_, states_[f], posed_, &posed_normals_);
        return;
    }
    const std::vector<Vector3d>& rest_normals = templates_.rest_normals();
    const Kinematics& kin = kin_[f];
    constexpr std::size_t kChunks = 8;
    const std::size_t n = vertex_sample_.size();
    pool_->parallel_for(kChunks, [&](std::size_t c, unsigned) {
        for (std::size_t s = c * n / kChunks; s < (c + 1) * n / kChunks; ++s) {
            const uint32_t v = vertex_sample_[s];
            posed_[v] = kin.posed_vertex(v, kin.rest_vertex(v));
            posed_normals_[v] = (kin.skin_rotation(v) * rest_normals[s]).normalized();
        }
    });
}

// The posed positions of the area-sampled vertex subset (posed_ must be current).
const std::vector<Vector3d>& FitProblem::posed_subset() {
    subset_posed_.resize(vertex_sample_.size());
    for (std::size_t i = 0; i < vertex_sample_.size(); ++i) subset_posed_[i] = posed_[vertex_sample_[i]];
    return subset_posed_;
}

void FitProblem::set_guides(uint32_t f, const std::vector<SurfacePoint>& points, const std::vector<Vector3d>& targets, double sigma) {
    clear_guides(f);
    FrameData& fd = frames_[f];
    const double weight = (o_.landmark_sigma / sigma) * (o_.landmark_sigma / sigma);
    for (std::size_t i = 0; i < points.size() && i < targets.size(); ++i) {
        fd.landmark_points.push_back(points[i]);
        fd.landmark_targets.push_back(targets[i]);
        fd.landmark_weights.push_back(weight);
    }
    ++pairs_version_;
}

void FitProblem::clear_guides(uint32_t f) {
    FrameData& fd = frames_[f];
    fd.landmark_points.resize(fd.own_landmarks);
    fd.landmark_targets.resize(fd.own_landmarks);
    fd.landmark_weights.resize(fd.own_landmarks);
    ++pairs_version_;
}

void FitProblem::find_pairs(const Stage& st, uint32_t frame_only) {
    pair_queries_.assign(F_, 0);
    for (uint32_t f = 0; f < F_; ++f) {
        if (frames_[f].points.empty() || (frame_only < F_ && f != frame_only)) continue;
        pose_frame(f, st.dense_model);
        find_frame_pairs(f, st);
    }
}

std::size_t FitProblem::pair_queries() const {
    std::size_t n = 0;
    for (std::size_t q : pair_queries_) n += q;
    return n;
}

// Correspondences both ways (correspondences.hpp; posed_ must be frame f's).
void FitProblem::find_frame_pairs(uint32_t f, const Stage& st) {
    auto& fd = frames_[f];
    fd.pairs.clear();
    ++pairs_version_;
    if (fd.points.empty() || st.point_fraction <= 0) return;
    // Model points for scan-to-model queries: all vertices or the subset (see Stage).
    GridIndex& model_index = st.dense_model ? dense_grid_ : sample_grid_;
    model_index.build(st.dense_model ? posed_ : posed_subset());
    PosedModel model;
    model.vertices = &posed_, model.normals = &posed_normals_, model.sample = &vertex_sample_;
    model.index = &model_index, model.dense = st.dense_model;
    PairGate gate;
    gate.max_distance = st.max_distance;
    gate.min_normal_dot = st.min_normal_dot;
    gate.scan_points = std::max<std::size_t>(16, std::min<std::size_t>(fd.scan_sample.size(), std::size_t(st.point_fraction * o_.max_points)));
    gate.model_points = std::max<std::size_t>(16, std::min<std::size_t>(vertex_sample_.size(), gate.scan_points));
    pair_queries_[f] += fitting::find_pairs(cloud_view(f), model, gate, *pool_, fd.pairs);
}

bool FitProblem::active(const Stage& st, uint32_t local) const {
    if (local < K_) return local < st.components;
    const uint32_t r = local - K_;
    if (r >= 3 * lin_.J) return r < 3 * lin_.J + 3 || o_.fit_scale;  // translation, scale
    const uint32_t j = r / 3;
    if (j == 0) return true;  // the root carries the global rotation
    if (st.all_joints) return true;
    // Coarse stages move the trunk and limbs, not the wrists (nor fingers and toes): their far-
    // reaching correspondences bent a hand over a hole in the scan onto the forearm's points,
    // and the fine stage could not bend it back (anatomy/joint_roles.hpp).
    return st.body_joints && pose_prior_.coarse(j);
}

// The columns a step solves for: active in the stage and, for joint rotations and frame
// parameters, touched by some data row in the last evaluate(). Joints nothing observes (the
// fingers, for landmarks) keep their value; leaving them out shrinks the system severalfold.
std::vector<int> FitProblem::solve_columns(const Stage& st) const {
    const std::vector<uint8_t>& touched = data_.touched();
    std::vector<int> cols;
    for (uint32_t f = 0; f < F_; ++f)
        for (uint32_t local = 0; local < K_ + B_; ++local) {
            if (f > 0 && local < K_) continue;
            const uint32_t c = local < K_ ? local : K_ + f * B_ + (local - K_);
            if (active(st, local) && (local < K_ || touched[c])) cols.push_back(int(c));
        }
    return cols;
}

void FitProblem::apply(const VectorXd& delta) {
    // Box constraint: the shape stays where the C API accepts it back (shape_range.hpp).
    for (uint32_t k = 0; k < K_; ++k) shape_[k] = within_shape_range(shape_[k] + delta[k]);
    std::vector<double> local(K_ + B_, 0.0);
    for (uint32_t f = 0; f < F_; ++f) {
        for (uint32_t i = 0; i < B_; ++i) local[K_ + i] = delta[K_ + f * B_ + i];
        kin_[f].apply(local.data(), states_[f]);
    }
}

double FitProblem::evaluate(const Stage& st, ArrowSystem* H, VectorXd* g, uint32_t frame_only) {
    // Only active parameters get rows: the rigid and coarse stages cost a fraction of the full one.
    const uint32_t PL = K_ + B_;
    std::vector<uint8_t> on(PL);
    for (uint32_t i = 0; i < PL; ++i) on[i] = active(st, i);
    // The blocks follow the correspondences: the trial steps of an iteration reuse them.
    if (blocks_pairs_ != pairs_version_ || blocks_frame_ != frame_only) {
        std::vector<Block> blocks;
        for (uint32_t f = 0; f < F_; ++f) {
            if (frame_only < F_ && f != frame_only) continue;
            const auto& fd = frames_[f];
            for (std::size_t i = 0; i < fd.landmark_points.size(); ++i)
                blocks.push_back({f, &fd.landmark_points[i], &fd.landmark_targets[i], nullptr,
                                  std::sqrt(fd.landmark_weights[i]) / o_.landmark_sigma});
            for (const auto& p : fd.pairs) blocks.push_back({f, &p.model, &p.target, &p.normal, std::sqrt(p.weight) / o_.point_sigma});
        }
        data_.set_blocks(std::move(blocks));
        blocks_pairs_ = pairs_version_, blocks_frame_ = frame_only;
    }
    double cost = data_.evaluate(kin_, on, st.gm_scale, H, g, *pool_);
    for (uint32_t f = 0; f < F_; ++f)
        if (frame_only >= F_ || f == frame_only) cost += pose_prior_.evaluate(kin_[f], states_[f], f * B_, H, g);
    add_shape_prior(shape_, o_.shape_prior, lin_.whole_body, o_.segment_prior, cost, H, g);
    return cost;
}

// Truncated squared distances both ways over fixed point sets (explained.hpp).
double FitProblem::explained(uint32_t f) {
    kin_[f].update(states_[f], false);
    pose_frame(f, false);
    sample_grid_.build(posed_subset());
    subset_normals_.resize(vertex_sample_.size());
    for (std::size_t i = 0; i < vertex_sample_.size(); ++i) subset_normals_[i] = posed_normals_[vertex_sample_[i]];
    return explained_measure(
        cloud_view(f), subset_posed_, subset_normals_,
        [&](const Vector3d& p) { return sample_grid_.nearest(p, kPlacementCap, nullptr); }, kPlacementCap, kExplainedSamples);
}

// The share of frame f's scan sample (its first kExplainedSamples points) farther than
// kUnexplainedDistance from the posed model and on a surface (kSurfaceNeighbours within
// kSurfaceRadius): a limb in the wrong place, a body turned over. Isolated points (outliers,
// sparse clutter) do not count.
double FitProblem::unexplained_share(uint32_t f) { return share_beyond(f, kUnexplainedDistance, false); }

double FitProblem::share_beyond(uint32_t f, double distance, bool every_vertex) {
    auto& fd = frames_[f];
    if (fd.points.empty()) return 0;
    kin_[f].update(states_[f], false);
    pose_frame(f, every_vertex);
    GridIndex& model_grid = every_vertex ? dense_grid_ : sample_grid_;
    model_grid.build(every_vertex ? posed_ : posed_subset());
    const std::size_t n = std::min(kExplainedSamples, fd.scan_sample.size());
    std::size_t far = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Vector3d& p = fd.points[fd.scan_sample[i]];
        if (model_grid.nearest(p, distance, nullptr) != GridIndex::kNone) continue;
        build_scan_tree(fd);
        uint32_t index[kSurfaceNeighbours + 1];
        double d2[kSurfaceNeighbours + 1];
        const std::size_t found = fd.scan_index->nearest_k(p, kSurfaceNeighbours + 1, index, d2);  // itself among them
        far += found == kSurfaceNeighbours + 1 && d2[kSurfaceNeighbours] <= kSurfaceRadius * kSurfaceRadius;
    }
    return double(far) / double(n);
}

double FitProblem::mean_scan_distance(uint32_t f, double cap) { return scan_distance_to_fit(f, cap, false); }

double FitProblem::mean_scan_plane_distance(uint32_t f, double cap) { return scan_distance_to_fit(f, cap, true); }

// Frame f posed (every vertex), then visit(point, its nearest posed vertex within cap or kNone,
// the squared distance to it or cap squared) for each scan point. Returns the number of points.
template <class Visit>
std::size_t FitProblem::visit_scan_nearest(uint32_t f, double cap, Visit&& visit) {
    const auto& fd = frames_[f];
    if (fd.points.empty()) return 0;
    kin_[f].update(states_[f], false);
    pose_frame(f, true);
    dense_grid_.build(posed_);
    for (const Vector3d& p : fd.points) {
        double d2 = cap * cap;
        const uint32_t v = dense_grid_.nearest(p, cap, &d2);
        visit(p, v, d2);
    }
    return fd.points.size();
}

double FitProblem::share_beyond_plane(uint32_t f, double distance, double cap) {
    std::size_t far = 0;
    const std::size_t n = visit_scan_nearest(f, cap, [&](const Vector3d& p, uint32_t v, double) {
        far += v == GridIndex::kNone || std::abs(posed_normals_[v].dot(p - posed_[v])) > distance;
    });
    return n ? double(far) / double(n) : 0;
}

std::vector<double> FitProblem::region_shares_beyond_plane(uint32_t f, double distance, double cap, const std::vector<uint8_t>& regions,
                                                           std::size_t region_count) {
    std::vector<double> share(region_count, 0.0), lesser_side(region_count, 0.0);
    region_sides_beyond_plane(f, distance, cap, regions, share.data(), lesser_side.data(), region_count);
    return share;
}

void FitProblem::region_sides_beyond_plane(uint32_t f, double distance, double cap, const std::vector<uint8_t>& regions, double* share,
                                           double* lesser_side, std::size_t region_count, double* near_count) {
    std::vector<double> front(region_count, 0.0), behind(region_count, 0.0), near(region_count, 0.0);
    visit_scan_nearest(f, cap, [&](const Vector3d& p, uint32_t v, double) {
        if (v == GridIndex::kNone || v >= regions.size() || regions[v] >= region_count) return;
        near[regions[v]] += 1;
        const double d = posed_normals_[v].dot(p - posed_[v]);
        front[regions[v]] += d > distance;
        behind[regions[v]] += d < -distance;
    });
    for (std::size_t r = 0; r < region_count; ++r) {
        const double far = front[r] + behind[r];
        share[r] = near[r] > 0 ? far / near[r] : 0.0;
        lesser_side[r] = far > 0 ? std::min(front[r], behind[r]) / far : 0.0;
        if (near_count) near_count[r] = near[r];
    }
}

// Each scan point's distance to its nearest posed vertex (or along that vertex's normal), capped;
// the mean over the frame's points.
double FitProblem::scan_distance_to_fit(uint32_t f, double cap, bool along_normal) {
    double sum = 0;
    const std::size_t n = visit_scan_nearest(f, cap, [&](const Vector3d& p, uint32_t v, double d2) {
        if (!along_normal || v == GridIndex::kNone) sum += std::sqrt(d2);
        else sum += std::min(cap, std::abs(posed_normals_[v].dot(p - posed_[v])));
    });
    return n ? sum / double(n) : 0;
}

const std::vector<Vector3d>& FitProblem::posed_sample(uint32_t f) {
    kin_[f].update(states_[f], false);
    pose_frame(f, false);
    return posed_subset();
}

LimbsInside FitProblem::limbs_inside(uint32_t f) {
    if (!inside_test_) inside_test_ = std::make_unique<InterpenetrationTest>(lin_);
    kin_[f].update(states_[f], false);
    pose_frame(f, true);
    return inside_test_->measure(posed_, posed_normals_);
}

const std::vector<uint8_t>& FitProblem::sample_regions() {
    if (sample_regions_.empty()) {
        const std::vector<uint8_t>& regions = vertex_regions();
        for (uint32_t v : vertex_sample_) sample_regions_.push_back(regions[v]);
    }
    return sample_regions_;
}

const std::vector<uint8_t>& FitProblem::vertex_regions() {
    if (vertex_regions_.empty()) vertex_regions_ = fitting::vertex_regions(lin_);
    return vertex_regions_;
}

const std::vector<uint8_t>& FitProblem::vertex_parts() {
    if (vertex_parts_.empty()) vertex_parts_ = fitting::vertex_parts(lin_);
    return vertex_parts_;
}

}  // namespace ssc::fitting
