// Which scan points lie on the rim of a hole or of the scan: a registration gives a template vertex
// whose nearest scan point is such a point no data term, so holes are filled with the template's
// shape (carried by smoothness) rather than pulled to their rim.
#pragma once

#include "common/thread_pool.hpp"
#include "fitting/nearest.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace ssc::registration {

// Point clouds: a point is on a boundary when its nearest neighbours, seen in its tangent plane,
// leave a gap wider than 90 degrees around it (an interior point is surrounded). normals: unit or
// zero (then the neighbours' plane). index: over points. Runs on the pool's threads.
std::vector<uint8_t> cloud_boundary(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                                    const fitting::PointIndex& index, ThreadPool& pool);

// Meshes: the vertices of edges that only one triangle uses.
std::vector<uint8_t> mesh_boundary(const std::vector<uint32_t>& triangles, std::size_t vertex_count);

}  // namespace ssc::registration
