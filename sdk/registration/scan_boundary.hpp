// Which scan points lie on the rim of a hole or of the scan: a registration gives a template vertex
// whose nearest scan point is such a point no data term, so holes are filled with the template's
// shape (carried by smoothness) rather than pulled to their rim.
#pragma once

#include "fitting/nearest.hpp"

#include <Eigen/Core>

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace ssc::registration {

// Meshes: the vertices of edges that only one triangle uses.
std::vector<uint8_t> mesh_boundary(const std::vector<uint32_t>& triangles, std::size_t vertex_count);

// A scan's rim as a registration asks for it: a mesh's up front; a cloud's point by point, tested
// the first time it is asked for (a point is on a cloud's rim when its 32 nearest neighbours,
// seen in its tangent plane, leave a gap wider than 90 degrees around it; an interior point is
// surrounded). A registration only asks about the
// points nearest the template, about a seventh of a 60,000-point booth scan's, so testing them
// all first took most of the time. Safe to ask from several threads; the arrays it was made
// from must outlive it.
class ScanRim {
public:
    ScanRim(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals, const fitting::PointIndex& index);
    ScanRim(const std::vector<uint32_t>& triangles, std::size_t vertex_count);
    bool operator()(uint32_t point) const;

private:
    const std::vector<Eigen::Vector3d>* points_ = nullptr;
    const std::vector<Eigen::Vector3d>* normals_ = nullptr;
    const fitting::PointIndex* index_ = nullptr;
    std::vector<uint8_t> mesh_rim_;
    std::unique_ptr<std::atomic<uint8_t>[]> tested_;  // per cloud point: 0 not yet, 1 inside, 2 rim
};

}  // namespace ssc::registration
