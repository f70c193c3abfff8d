// The template the automatic start search places (rigid_start.hpp): the mean body at rest and in
// each start pose (sitting, crouching, bending forward), as its area-uniform vertex sample with a
// k-d tree and its principal frame. Built on first use, then fixed for the fit.
#pragma once

#include "fitting/extremities.hpp"
#include "fitting/kinematics.hpp"
#include "fitting/nearest.hpp"
#include "fitting/rigid_start.hpp"
#include "synthesis/body.hpp"

#include <array>
#include <memory>
#include <vector>

namespace ssc::fitting {

// The poses the start search tries besides the rest pose (anatomy/named_poses.cpp): scans of
// people crouching, bent forward or seated have other principal axes than a standing body's, and
// a fit started from the rest pose ended upside down or standing (hard poses of the benchmark).
// The first kFirstStartPoses are tried in the first start search; all of them in the restarts
// from the start poses placed again (solver.cpp, placed_again()).
constexpr const char* kStartPoses[] = {"sitting", "crouching", "bending_forward", "touching_toes"};
constexpr std::size_t kFirstStartPoses = 3;

// The template (mean shape) in one pose.
struct StartTemplate {
    std::vector<Eigen::Quaterniond> pose;
    std::vector<Vector3d> points, normals;  // the vertex sample posed
    std::unique_ptr<PointIndex> index;      // over points
    Vector3d centre = Vector3d::Zero();
    double bottom = 0, top = 0;
    Matrix3d frame = Matrix3d::Identity();
    RestSample sample() const;
};

// Not thread-safe (built lazily). body: of the fit's model, used to pose the template (its state
// is left changed); vertex_sample: the fit's area-uniform sample. Both must outlive this.
class StartTemplates {
public:
    StartTemplates(const LinearModel& lin, Body& body, const std::vector<uint32_t>& vertex_sample);

    // The mean body at rest: the model frame, the body's centre and height.
    RestSample rest();
    // Unit normals of the vertex sample at rest, in the sample's order.
    const std::vector<Vector3d>& rest_normals();

    // The mean body's head, hands and feet at rest (extremities.hpp) and their guides' places there.
    const ModelTips& tips();
    const std::array<Vector3d, kTipCount>& rest_tips();

    // The mean body in each of kStartPoses; none for a model without joint limits (its poses
    // could not be made).
    const std::vector<StartTemplate>& posed();

private:
    const LinearModel& lin_;
    Body& body_;
    const std::vector<uint32_t>& vertex_sample_;
    StartTemplate rest_;      // pose empty until built
    bool rest_built_ = false;
    std::vector<StartTemplate> posed_;
    bool tips_built_ = false;
    ModelTips tips_;
    std::array<Vector3d, kTipCount> rest_tips_{};
    std::vector<Vector3d> vertices_, normals_;  // scratch: the posed surface
};

}  // namespace ssc::fitting
