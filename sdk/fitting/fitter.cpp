#include "fitting/fitter.hpp"

#include "common/error.hpp"
#include "fitting/nearest.hpp"
#include "fitting/posed_surface.hpp"
#include "synthesis/body.hpp"

#include <string>

namespace ssc::fitting {

namespace {

FitOptions checked(const Model& model, FitOptions o) {
    // A model without components (a template alone) is fitted in pose only.
    SSC_REQUIRE_ARG_S((o.components >= 1 || model.component_count() == 0) && o.components <= model.component_count(),
                      "fitter: " << o.components << " shape components; the model has " << model.component_count());
    SSC_REQUIRE_ARG(o.max_iterations >= 3, "fitter: max_iterations must be at least 3");
    SSC_REQUIRE_ARG(std::isfinite(o.landmark_sigma) && o.landmark_sigma > 0, "fitter: landmark_sigma must be positive");
    SSC_REQUIRE_ARG(std::isfinite(o.point_sigma) && o.point_sigma > 0, "fitter: point_sigma must be positive");
    SSC_REQUIRE_ARG(std::isfinite(o.shape_prior) && o.shape_prior >= 0, "fitter: shape_prior must be >= 0");
    SSC_REQUIRE_ARG(std::isfinite(o.pose_prior) && o.pose_prior >= 0, "fitter: pose_prior must be >= 0");
    SSC_REQUIRE_ARG(o.max_points >= 16, "fitter: max_points must be at least 16");
    return o;
}

}  // namespace

Fitter::Fitter(const Model& model, const FitOptions& options, std::shared_ptr<const anatomy::ModelAnatomy> anatomy)
    : options_(checked(model, options)),
      linear_(model, options_.components, std::move(anatomy), options_.segments && options_.components == model.component_count()) {}

const Frame& Fitter::frame(uint32_t frame) const {
    SSC_REQUIRE_ARG_S(frame < frames_.size(), "frame " << frame << " out of range (" << frames_.size() << " frames)");
    return frames_[frame];
}

Frame& Fitter::frame_for_adding(uint32_t frame) {
    SSC_REQUIRE_ARG_S(frame <= frames_.size(), "frame " << frame << " is beyond the next new frame (" << frames_.size() << ")");
    if (frame == frames_.size()) frames_.emplace_back();
    solved_ = false;
    return frames_[frame];
}

void Fitter::add_landmarks(uint32_t frame, const std::vector<LandmarkTarget>& targets) {
    for (std::size_t i = 0; i < targets.size(); ++i) validate_landmark(model().data(), targets[i], "landmark " + std::to_string(i));
    SSC_REQUIRE_ARG_S(frame <= frames_.size(), "frame " << frame << " is beyond the next new frame (" << frames_.size() << ")");
    // One landmark twice in a frame is two positions for one point: a caller's mistake (a file
    // listing names twice), never a measurement to average.
    std::vector<uint8_t> given(model().data().landmarks.size(), 0);
    if (frame < frames_.size())
        for (const auto& l : frames_[frame].landmarks) given[l.landmark] = 1;
    for (const auto& l : targets) {
        SSC_REQUIRE_ARG_S(!given[l.landmark], "landmark " << model().data().landmarks[l.landmark].name << " is given twice in frame " << frame);
        given[l.landmark] = 1;
    }
    Frame& f = frame_for_adding(frame);
    f.landmarks.insert(f.landmarks.end(), targets.begin(), targets.end());
}

void Fitter::add_cloud(uint32_t frame, PointCloud cloud) {
    SSC_REQUIRE_ARG_S(cloud.points.size() >= 16, "a cloud needs at least 16 points, not " << cloud.points.size());
    validate_cloud(cloud, "cloud");
    frame_for_adding(frame).clouds.push_back(std::move(cloud));
}

uint32_t Fitter::add_depth_image(uint32_t frame, const DepthView& image) {
    SSC_REQUIRE_ARG_S(frame <= frames_.size(), "frame " << frame << " is beyond the next new frame (" << frames_.size() << ")");
    PointCloud cloud = depth_to_cloud(image);
    const uint32_t n = uint32_t(cloud.points.size());
    frame_for_adding(frame).clouds.push_back(std::move(cloud));
    return n;
}

uint32_t Fitter::point_count(uint32_t frame) const {
    if (frame >= frames_.size()) return 0;
    std::size_t n = 0;
    for (const auto& c : frames_[frame].clouds) n += c.points.size();
    return uint32_t(n);
}

void Fitter::clear() {
    frames_.clear();
    solved_ = false;
    solution_ = {};
    residuals_.clear();
}

const FitReport& Fitter::solve(const FitProgress& progress, ThreadPool* pool, const FrameDone& frame_done) {
    solved_ = false;
    solution_ = fit(linear_, frames_, options_, nullptr, progress, pool, frame_done);
    residuals_.assign(frames_.size(), {});
    Body body(model(), nullptr);
    std::vector<Vector3d> posed, normals;
    for (std::size_t f = 0; f < frames_.size(); ++f) {
        if (frames_[f].clouds.empty()) continue;
        posed_surface(body, solution_.frames[f], posed, &normals);
        const PointIndex index(posed);
        for (const auto& c : frames_[f].clouds)
            for (const auto& p : c.points) {
                const uint32_t v = index.nearest(p, nullptr);
                residuals_[f].push_back(float(std::abs(normals[v].dot(p - posed[v]))));
            }
    }
    solved_ = true;
    return solution_.report;
}

const FitSolution& Fitter::solution() const {
    SSC_REQUIRE_ARG(solved_, "no successful solve yet");
    return solution_;
}

const FitState& Fitter::frame_state(uint32_t frame) const {
    const FitSolution& s = solution();
    SSC_REQUIRE_ARG_S(frame < s.frames.size(), "frame " << frame << " out of range (" << s.frames.size() << " frames)");
    return s.frames[frame];
}

std::vector<Vector3d> Fitter::vertices(uint32_t frame) const {
    const FitState& s = frame_state(frame);
    Body body(model(), nullptr);
    std::vector<Vector3d> posed;
    posed_surface(body, s, posed);
    return posed;
}

const std::vector<float>& Fitter::point_residuals(uint32_t frame) const {
    frame_state(frame);  // solved, in range
    return residuals_[frame];
}

}  // namespace ssc::fitting
