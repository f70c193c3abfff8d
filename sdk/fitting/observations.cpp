#include "fitting/observations.hpp"

#include "common/error.hpp"
#include "sscape_format/model_data.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace ssc::fitting {

bool measured_point(const Vector3d& p) { return p.allFinite() && p.cwiseAbs().maxCoeff() <= kMaxCoordinate; }

void validate_landmark(const format::ModelData& model, const LandmarkTarget& l, const std::string& where) {
    SSC_REQUIRE_ARG_S(l.landmark < model.landmarks.size(),
                      where << ": landmark index " << l.landmark << " is out of range (the model has " << model.landmarks.size() << ")");
    SSC_REQUIRE_ARG_S(measured_point(l.position), where << ": landmark " << model.landmarks[l.landmark].name
                                                        << " is not finite or has a coordinate beyond " << kMaxCoordinate);
    SSC_REQUIRE_ARG_S(l.weight > 0 && std::isfinite(l.weight), where << ": landmark weights must be positive");
}

void validate_cloud(const PointCloud& c, const std::string& where) {
    SSC_REQUIRE_ARG_S(c.normals.empty() || c.normals.size() == c.points.size(),
                      where << ": " << c.normals.size() << " normals for " << c.points.size() << " points");
    SSC_REQUIRE_ARG_S(c.confidence.empty() || c.confidence.size() == c.points.size(),
                      where << ": " << c.confidence.size() << " confidences for " << c.points.size() << " points");
    for (std::size_t i = 0; i < c.points.size(); ++i) {
        SSC_REQUIRE_ARG_S(measured_point(c.points[i]), where << ": point " << i << " is not finite or has a coordinate beyond " << kMaxCoordinate);
        if (!c.normals.empty())
            SSC_REQUIRE_ARG_S(c.normals[i].allFinite() && (c.normals[i].squaredNorm() == 0 || std::abs(c.normals[i].norm() - 1) < 1e-3),
                              where << ": normal " << i << " is neither a unit vector nor zero (unknown)");
        if (!c.confidence.empty())
            SSC_REQUIRE_ARG_S(c.confidence[i] >= 0 && c.confidence[i] <= 1, where << ": confidence " << i << " is not in [0, 1]");
    }
}

void validate_spread(const std::vector<const std::vector<Vector3d>*>& clouds, const std::string& where) {
    std::size_t n = 0;
    for (const auto* c : clouds) n += c->size();
    if (n == 0) return;
    // Distinct 1 cm cells: a body's surface fills thousands; a cloud needs min(100, n / 4).
    const std::size_t needed = std::min<std::size_t>(100, std::max<std::size_t>(1, n / 4));
    std::unordered_set<uint64_t> cells;
    Vector3d mean = Vector3d::Zero();
    for (const auto* c : clouds)
        for (const Vector3d& p : *c) {
            mean += p;
            if (cells.size() >= needed) continue;
            const Eigen::Array3d q = (p.array() / 0.01).floor();
            const uint64_t key = (uint64_t(int64_t(q[0]) & 0x1FFFFF) << 42) | (uint64_t(int64_t(q[1]) & 0x1FFFFF) << 21) | uint64_t(int64_t(q[2]) & 0x1FFFFF);
            cells.insert(key);
        }
    SSC_REQUIRE_ARG_S(cells.size() >= needed, where << ": its " << n << " points lie at only " << cells.size()
                                                    << " places (1 cm apart): not a scan of a body (duplicated or collapsed points)");
    mean /= double(n);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto* c : clouds)
        for (const Vector3d& p : *c) cov += (p - mean) * (p - mean).transpose();
    cov /= double(n);
    const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly).eigenvalues().cwiseMax(0).cwiseSqrt();
    // A body (a hand, a face) is at least centimetres thick in every direction; a wall is not.
    SSC_REQUIRE_ARG_S(!(spread[0] < 0.003 && spread[2] > 0.05), where << ": its points lie in one plane (" << 1e3 * spread[0]
                                                                        << " mm thick over " << 1e3 * spread[2] << " mm): a wall or a floor, not a body");
}

void validate_frame(const format::ModelData& model, const Frame& frame, const std::string& where) {
    for (const auto& l : frame.landmarks) validate_landmark(model, l, where);
    std::size_t points = 0;
    std::vector<const std::vector<Vector3d>*> clouds;
    for (const auto& c : frame.clouds) {
        validate_cloud(c, where);
        points += c.points.size();
        clouds.push_back(&c.points);
    }
    SSC_REQUIRE_ARG_S(frame.landmarks.size() >= 3 || points >= 16, where << " has too little data (at least 3 landmarks or 16 points)");
    validate_spread(clouds, where);
}

}  // namespace ssc::fitting
