#include "fitting/start_templates.hpp"

#include "anatomy/named_poses.hpp"
#include "fitting/posed_surface.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>

namespace ssc::fitting {

namespace {
// The centre, frame and height use every this many vertices of the whole surface.
constexpr uint32_t kEvery = 7;
}  // namespace

RestSample StartTemplate::sample() const {
    RestSample r;
    r.points = &points, r.normals = &normals, r.index = index.get();
    r.centre = centre, r.bottom = bottom, r.top = top, r.frame = frame;
    return r;
}

StartTemplates::StartTemplates(const LinearModel& lin, Body& body, const std::vector<uint32_t>& vertex_sample)
    : lin_(lin), body_(body), vertex_sample_(vertex_sample) {}

RestSample StartTemplates::rest() {
    if (!rest_built_) {
        rest_built_ = true;
        FitState zero;
        zero.shape.assign(lin_.K, 0.0);
        zero.pose.assign(lin_.J, Eigen::Quaterniond::Identity());
        posed_surface(body_, zero, vertices_, &normals_);
        for (uint32_t v : vertex_sample_) rest_.points.push_back(vertices_[v]), rest_.normals.push_back(normals_[v]);
        rest_.index = std::make_unique<PointIndex>(rest_.points);
        // The model frame; the height along y.
        rest_.centre.setZero();
        rest_.bottom = 1e9, rest_.top = -1e9;
        for (uint32_t v = 0; v < lin_.V; v += kEvery) {
            rest_.centre += vertices_[v];
            rest_.bottom = std::min(rest_.bottom, vertices_[v].y()), rest_.top = std::max(rest_.top, vertices_[v].y());
        }
        rest_.centre /= double((lin_.V + kEvery - 1) / kEvery);
    }
    return rest_.sample();
}

const std::vector<Vector3d>& StartTemplates::rest_normals() {
    rest();
    return rest_.normals;
}

const ModelTips& StartTemplates::tips() {
    if (!tips_built_) {
        tips_built_ = true;
        FitState zero;
        zero.shape.assign(lin_.K, 0.0);
        zero.pose.assign(lin_.J, Eigen::Quaterniond::Identity());
        std::vector<Vector3d> vertices;
        posed_surface(body_, zero, vertices, nullptr);
        const auto& triangles = lin_.model.data().mesh.triangles;
        tips_ = model_tips(vertices, triangles.data(), triangles.size() / 3, tip_parts(lin_));
        if (tips_.valid)
            for (std::size_t t = 0; t < kTipCount; ++t) rest_tips_[t] = vertices[tips_.guide[t]];
    }
    return tips_;
}

const std::array<Vector3d, kTipCount>& StartTemplates::rest_tips() {
    tips();
    return rest_tips_;
}

const std::vector<StartTemplate>& StartTemplates::posed() {
    if (!posed_.empty() || !lin_.model.data().joint_limits.size()) return posed_;
    // In place: a PointIndex refers to its points vector, so templates never move once built.
    posed_.reserve(std::size(kStartPoses));
    for (const char* name : kStartPoses) {
        StartTemplate& t = posed_.emplace_back();
        const std::vector<float> q = anatomy::named_pose(lin_.model, name, &lin_.limits);
        for (uint32_t j = 0; j < lin_.J; ++j) t.pose.emplace_back(q[4 * j + 3], q[4 * j], q[4 * j + 1], q[4 * j + 2]);
        FitState st;
        st.shape.assign(lin_.K, 0.0);
        st.pose = t.pose;
        posed_surface(body_, st, vertices_, &normals_);
        for (uint32_t v : vertex_sample_) t.points.push_back(vertices_[v]), t.normals.push_back(normals_[v]);
        t.index = std::make_unique<PointIndex>(t.points);
        Matrix3d cov = Matrix3d::Zero();
        for (uint32_t v = 0; v < lin_.V; v += kEvery) t.centre += vertices_[v];
        t.centre /= double((lin_.V + kEvery - 1) / kEvery);
        for (uint32_t v = 0; v < lin_.V; v += kEvery) cov += (vertices_[v] - t.centre) * (vertices_[v] - t.centre).transpose();
        // The principal frame: across, the longest axis (up), the second.
        const Eigen::SelfAdjointEigenSolver<Matrix3d> es(cov);
        const Vector3d up = es.eigenvectors().col(2), second = es.eigenvectors().col(1);
        t.frame.col(1) = up;
        t.frame.col(2) = second;
        t.frame.col(0) = up.cross(second);
        t.bottom = 1e9, t.top = -1e9;
        for (uint32_t v = 0; v < lin_.V; v += kEvery) {
            const double h = (vertices_[v] - t.centre).dot(up);
            t.bottom = std::min(t.bottom, h), t.top = std::max(t.top, h);
        }
        t.bottom += t.centre.dot(up), t.top += t.centre.dot(up);
    }
    return posed_;
}

}  // namespace ssc::fitting
