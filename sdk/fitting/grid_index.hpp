// Nearest-neighbour queries within a radius over a small point set that is rebuilt often: a uniform
// grid, built in one counting-sort pass.
//
// Why not the k-d tree (nearest.hpp): the limb search re-poses a limb about a thousand times per
// fit and needs, each time, the nearest re-posed vertex of a few hundred scan points. Building a
// k-d tree over the limb's vertices cost more than all those queries together; the grid builds
// in a few microseconds, and the queries are bounded by the search radius the caller needs anyway.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace ssc::fitting {

class GridIndex {
public:
    static constexpr uint32_t kNone = 0xFFFFFFFFu;

    // cell: edge length in metres, about twice the points' typical spacing.
    explicit GridIndex(double cell) : base_cell_(cell), cell_(cell) {}

    // Indexes the points (referenced, not copied: they must outlive the queries and stay
    // unchanged). Buffers are reused between builds.
    void build(const std::vector<Eigen::Vector3d>& points);

    // The nearest point closer than `radius` to q and its squared distance, or kNone (dist2
    // untouched) when there is none. Exact; the same answer every time for the same build.
    uint32_t nearest(const Eigen::Vector3d& q, double radius, double* dist2) const;

private:
    double base_cell_, cell_;  // cell_: base_cell_, or larger for a widely spread set
    const std::vector<Eigen::Vector3d>* points_ = nullptr;
    Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d lo_ = Eigen::Vector3d::Zero(), hi_ = Eigen::Vector3d::Zero();  // the points' bounding box
    int dims_[3] = {0, 0, 0};
    std::vector<uint32_t> start_;  // per cell, into order_; one past the end last
    std::vector<uint32_t> order_;  // point indices by cell
    std::vector<uint32_t> cell_of_, next_;  // build scratch
};

}  // namespace ssc::fitting
