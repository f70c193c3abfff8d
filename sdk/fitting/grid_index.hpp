// Nearest-neighbour queries within a radius: a uniform grid, built in one counting-sort pass.
//
// Why a grid and not the k-d tree (nearest.hpp) for most of the fit: the model's posed vertices
// change every iteration, and the limb search re-poses a limb about a thousand times per fit.
// Building a k-d tree over 13,000 vertices costs about 4 ms, several times the queries that
// follow; the grid builds in a tenth of that. Every query of the fit has a radius anyway (a
// correspondence gate, the cap of a truncated distance), which bounds the grid's search. Queries
// with no useful radius (the start search, whose candidates begin tens of centimetres off) stay
// with the k-d tree.
//
// Threads: nearest() may run on many threads at once; build() must run alone.
#pragma once

#include "common/thread_pool.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace ssc::fitting {

class GridIndex {
public:
    static constexpr uint32_t kNone = 0xFFFFFFFFu;

    // cell: edge length in metres, about twice the points' typical spacing. The grid never has
    // more than kMaxCells cells: a widely spread set (a stray far point) gets larger cells.
    explicit GridIndex(double cell) : base_cell_(cell) {}

    // Indexes the points (copied in cell order, so the set may change after the build). Buffers
    // are reused between builds.
    void build(const std::vector<Eigen::Vector3d>& points);

    // Optional, after build(): records for every cell how many shells of cells around it are
    // empty (up to max_shells), so queries skip them. Queries far from every point (a model vertex
    // over a hole in a scan, or behind a depth image's visible side) then end at once instead of
    // visiting every cell within their radius. It costs two passes over the cells per axis: worth
    // it for a set built once and queried many times (a scan), not for one rebuilt per iteration.
    // The passes run on the pool's threads; the result does not depend on their number.
    void index_empty_space(int max_shells, ThreadPool& pool);

    // The nearest point closer than `radius` to q and its squared distance, or kNone (dist2
    // untouched) when there is none. Exact; the same answer every time for the same build.
    uint32_t nearest(const Eigen::Vector3d& q, double radius, double* dist2) const;

private:
    static constexpr double kMaxCells = 1 << 18;  // 1 MB of cell starts

    double base_cell_;
    double cell_ = 0, inverse_cell_ = 0;  // the cell used: base_cell_, or larger for a widely spread set
    Eigen::Vector3d lo_ = Eigen::Vector3d::Zero(), hi_ = Eigen::Vector3d::Zero();  // the points' bounding box; lo_ is the grid's origin
    int dims_[3] = {0, 0, 0};                 // cells per axis; x varies fastest
    std::vector<uint32_t> start_;             // per cell, into sorted_; one past the end last
    std::vector<Eigen::Vector3d> sorted_;     // the points by cell
    std::vector<uint32_t> original_;          // their indices in the built set
    std::vector<uint32_t> cell_of_;           // build scratch
    std::vector<uint8_t> empty_shells_;       // per cell (index_empty_space), or empty
    bool brute_force_ = false;                // the set's extent overflowed: no cells, every point tried
};

}  // namespace ssc::fitting
