// The closest point of a triangle mesh to query points, exact, for building detail levels: a level's
// vertices and landmarks are placed on the body by it (thousands of queries against 26,000
// triangles; by brute force that was most of a training run's time).
#pragma once

#include "fitting/nearest.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace ssc::training {

// The closest point of triangle abc to p, as barycentric weights.
std::array<double, 3> closest_barycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// Closest-point queries on a mesh (xyz: 3 floats a vertex; triangles: 3 indices each). The arrays
// are referenced, not copied: they must outlive the index and stay unchanged.
class MeshClosest {
public:
    MeshClosest(const std::vector<float>& xyz, const std::vector<uint32_t>& triangles);

    // The triangle holding the closest point to p and the point's barycentric weights; of triangles
    // equally close, the first (as a scan of every triangle in order gives). A mesh without
    // triangles gives triangle 0, weights (1, 0, 0).
    std::pair<uint32_t, std::array<double, 3>> operator()(const Eigen::Vector3d& p) const;

private:
    const std::vector<float>& xyz_;
    const std::vector<uint32_t>& triangles_;
    std::vector<Eigen::Vector3d> centroids_;
    double reach_ = 0;  // the largest distance of a triangle's corner from its centroid
    std::unique_ptr<fitting::PointIndex> index_;
};

}  // namespace ssc::training
