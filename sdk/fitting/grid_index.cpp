#include "fitting/grid_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ssc::fitting {

namespace {

// At most this many cells per axis: a stray far point must not make the grid huge (the cell
// grows instead).
constexpr int kMaxCellsPerAxis = 64;

}  // namespace

void GridIndex::build(const std::vector<Eigen::Vector3d>& points) {
    points_ = &points;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    if (points.empty()) lo = hi = Eigen::Vector3d::Zero();
    double cell = base_cell_;
    for (int a = 0; a < 3; ++a) cell = std::max(cell, (hi[a] - lo[a]) / (kMaxCellsPerAxis - 1));
    cell_ = cell;
    origin_ = lo;
    lo_ = lo, hi_ = hi;
    std::size_t cells = 1;
    for (int a = 0; a < 3; ++a) {
        dims_[a] = int((hi[a] - lo[a]) / cell) + 1;
        cells *= std::size_t(dims_[a]);
    }
    start_.assign(cells + 1, 0);
    cell_of_.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        std::size_t c = 0;
        for (int a = 2; a >= 0; --a) c = c * std::size_t(dims_[a]) + std::size_t(std::min(dims_[a] - 1, int((points[i][a] - lo[a]) / cell)));
        cell_of_[i] = uint32_t(c);
        ++start_[c + 1];
    }
    for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
    order_.resize(points.size());
    next_.assign(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < points.size(); ++i) order_[next_[cell_of_[i]]++] = uint32_t(i);
}

uint32_t GridIndex::nearest(const Eigen::Vector3d& q, double radius, double* dist2) const {
    if (!points_ || points_->empty()) return kNone;
    // Most queries of the limb search are far from the limb: the bounding box answers them.
    double outside2 = 0;
    for (int a = 0; a < 3; ++a) {
        const double below = lo_[a] - q[a], above = q[a] - hi_[a];
        if (below > 0) outside2 += below * below;
        if (above > 0) outside2 += above * above;
    }
    if (outside2 >= radius * radius) return kNone;
    int qc[3];
    for (int a = 0; a < 3; ++a) {
        const double x = std::floor((q[a] - origin_[a]) / cell_);
        qc[a] = int(std::clamp(x, 0.0, double(dims_[a] - 1)));
    }
    double best = radius * radius;
    uint32_t found = kNone;
    auto visit = [&](int x, int y, int z) {
        const std::size_t c = (std::size_t(z) * std::size_t(dims_[1]) + std::size_t(y)) * std::size_t(dims_[0]) + std::size_t(x);
        for (uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
            const uint32_t i = order_[k];
            const double d2 = ((*points_)[i] - q).squaredNorm();
            if (d2 < best) best = d2, found = i;
        }
    };
    // Shells of cells around q's cell, nearest first, clipped to the grid.
    for (int s = 0;; ++s) {
        // Points in cells s or more away (Chebyshev, in cells) are at least s - 1 cells away.
        const double gap = double(s - 1) * cell_;
        if (s > 0 && gap * gap >= best) break;
        int lo[3], hi[3];
        bool inside = false;  // some cell of this shell lies in the grid
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::max(qc[a] - s, 0), hi[a] = std::min(qc[a] + s, dims_[a] - 1);
            inside |= qc[a] - s >= 0 || qc[a] + s < dims_[a];
        }
        if (!inside) break;
        for (int x = lo[0]; x <= hi[0]; ++x)
            for (int y = lo[1]; y <= hi[1]; ++y) {
                if (std::abs(x - qc[0]) == s || std::abs(y - qc[1]) == s) {
                    for (int z = lo[2]; z <= hi[2]; ++z) visit(x, y, z);
                } else {
                    if (qc[2] - s >= 0) visit(x, y, qc[2] - s);
                    if (s > 0 && qc[2] + s < dims_[2]) visit(x, y, qc[2] + s);
                }
            }
    }
    if (found != kNone && dist2) *dist2 = best;
    return found;
}

}  // namespace ssc::fitting
