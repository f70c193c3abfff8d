#include "registration/scan_boundary.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace ssc::registration {

namespace {
// Neighbours looked at: enough to surround an interior point of a randomly sampled scan (with 16,
// a quarter of a simulated scan's points had a gap over 90 degrees; with 32, 4 %, most of them
// at its holes), few enough to see a hole of a few point spacings.
constexpr std::size_t kNeighbours = 32;
constexpr double kGap = M_PI / 2;

// Point clouds: a point is on a boundary when its nearest neighbours, seen in its tangent plane,
// leave a gap wider than 90 degrees around it (an interior point is surrounded). normals: unit or
// zero (then the neighbours' plane).
bool on_cloud_boundary(std::size_t i, const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                       const fitting::PointIndex& index) {
    uint32_t idx[kNeighbours + 1];
    double d2[kNeighbours + 1], angle[kNeighbours + 1];
    const std::size_t found = index.nearest_k(points[i], kNeighbours + 1, idx, d2);
    Eigen::Vector3d n = normals.empty() ? Eigen::Vector3d::Zero() : normals[i];
    if (n.squaredNorm() == 0) {  // the neighbours' plane
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (std::size_t k = 0; k < found; ++k) mean += points[idx[k]];
        mean /= double(found);
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        for (std::size_t k = 0; k < found; ++k) cov += (points[idx[k]] - mean) * (points[idx[k]] - mean).transpose();
        n = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);
    }
    const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
    std::size_t count = 0;
    for (std::size_t k = 0; k < found; ++k) {
        if (idx[k] == i) continue;
        const Eigen::Vector3d d = points[idx[k]] - points[i];
        if (d.squaredNorm() == 0) continue;
        angle[count++] = std::atan2(d.dot(v), d.dot(u));
    }
    if (count < 3) return true;
    std::sort(angle, angle + count);
    double gap = angle[0] + 2 * M_PI - angle[count - 1];
    for (std::size_t k = 1; k < count; ++k) gap = std::max(gap, angle[k] - angle[k - 1]);
    return gap > kGap;
}

}  // namespace

std::vector<uint8_t> mesh_boundary(const std::vector<uint32_t>& triangles, std::size_t vertex_count) {
    std::map<std::pair<uint32_t, uint32_t>, int> uses;
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = triangles[t + std::size_t(e)], b = triangles[t + std::size_t((e + 1) % 3)];
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    std::vector<uint8_t> out(vertex_count, 0);
    for (const auto& [edge, count] : uses)
        if (count == 1 && edge.first < vertex_count && edge.second < vertex_count) out[edge.first] = out[edge.second] = 1;
    return out;
}

ScanRim::ScanRim(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                 const fitting::PointIndex& index)
    : points_(&points), normals_(&normals), index_(&index), tested_(new std::atomic<uint8_t>[points.size()]()) {}

ScanRim::ScanRim(const std::vector<uint32_t>& triangles, std::size_t vertex_count) : mesh_rim_(mesh_boundary(triangles, vertex_count)) {}

bool ScanRim::operator()(uint32_t point) const {
    if (!tested_) return point < mesh_rim_.size() && mesh_rim_[point];
    if (points_->size() <= kNeighbours) return true;
    // Two threads may test the same point at once: both find the same.
    uint8_t t = tested_[point].load(std::memory_order_relaxed);
    if (t == 0) {
        t = on_cloud_boundary(point, *points_, *normals_, *index_) ? 2 : 1;
        tested_[point].store(t, std::memory_order_relaxed);
    }
    return t == 2;
}

}  // namespace ssc::registration
