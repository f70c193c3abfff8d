// Distances from points to a triangle mesh's surface, for points near it: the exact distance to the
// triangles around the point's nearest vertex (its one ring). On a fine mesh (the body's edges are
// about 1 cm) that is the surface distance for points within a few centimetres, where the nearest
// vertex alone is up to half an edge off; farther away it may overestimate, which does not matter
// to a caller asking whether a point lies beyond a few millimetres.
#pragma once

#include "fitting/nearest.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ssc::fitting {

// The distance from p to the triangle abc (its closest point by the triangle's Voronoi regions).
double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               const Eigen::Vector3d& c);

class SurfaceDistance {
public:
    // The vertices are referenced (they must outlive this and stay unchanged); triangles: 3 vertex
    // indices each, all below vertices.size().
    SurfaceDistance(const std::vector<Eigen::Vector3d>& vertices, const uint32_t* triangles, std::size_t triangle_count);
    double operator()(const Eigen::Vector3d& q) const;

private:
    const std::vector<Eigen::Vector3d>& vertices_;
    std::vector<uint32_t> triangles_;
    std::vector<uint32_t> ring_offsets_, ring_;  // each vertex's triangles (CSR)
    PointIndex index_;
};

// The share of `points` farther than `distance` from the surface.
double share_beyond_surface(const SurfaceDistance& surface, const std::vector<Eigen::Vector3d>& points, double distance);

}  // namespace ssc::fitting
