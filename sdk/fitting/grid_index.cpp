#include "fitting/grid_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ssc::fitting {

void GridIndex::build(const std::vector<Eigen::Vector3d>& points) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    if (points.empty()) lo = hi = Eigen::Vector3d::Zero();
    // A set whose extent overflows (callers reject such coordinates, but the grid must not divide
    // by infinity) is searched point by point.
    brute_force_ = !(hi - lo).allFinite();
    if (brute_force_) {
        sorted_ = points;
        original_.resize(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) original_[i] = uint32_t(i);
        return;
    }
    double cell = base_cell_;
    auto cells_for = [&](double c) {
        double n = 1;
        for (int a = 0; a < 3; ++a) n *= std::floor((hi[a] - lo[a]) / c) + 1;
        return n;
    };
    while (cells_for(cell) > kMaxCells) cell *= 1.25;
    cell_ = cell, inverse_cell_ = 1 / cell;
    lo_ = lo, hi_ = hi;
    std::size_t cells = 1;
    for (int a = 0; a < 3; ++a) {
        dims_[a] = int((hi[a] - lo[a]) * inverse_cell_) + 1;
        cells *= std::size_t(dims_[a]);
    }
    // Counting sort by cell: start_[c + 1] counts cell c, then prefix sums give each cell's first
    // slot; filling advances start_[c], after which start_ is shifted back by one.
    start_.assign(cells + 1, 0);
    cell_of_.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        std::size_t c = 0;
        for (int a = 2; a >= 0; --a)
            c = c * std::size_t(dims_[a]) + std::size_t(std::min(dims_[a] - 1, int((points[i][a] - lo[a]) * inverse_cell_)));
        cell_of_[i] = uint32_t(c);
        ++start_[c + 1];
    }
    for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
    sorted_.resize(points.size());
    original_.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const uint32_t k = start_[cell_of_[i]]++;
        sorted_[k] = points[i];
        original_[k] = uint32_t(i);
    }
    for (std::size_t c = cells; c > 0; --c) start_[c] = start_[c - 1];
    start_[0] = 0;
    empty_shells_.clear();
}

void GridIndex::index_empty_space(int max_shells, ThreadPool& pool) {
    empty_shells_.clear();
    if (brute_force_ || sorted_.empty()) return;
    max_shells = std::clamp(max_shells, 0, 254);
    // The Chebyshev distance (in cells) from each cell to the nearest non-empty one, capped:
    // min over non-empty n of max(|dx|, |dy|, |dz|) nests into one pass per axis, each
    // d'(c) = min over |t| <= cap of max(|t|, d(c + t e_axis)).
    const int cap = max_shells + 1;
    const std::size_t cells = start_.size() - 1;
    std::vector<uint8_t> d(cells), next(cells);
    for (std::size_t c = 0; c < cells; ++c) d[c] = start_[c + 1] > start_[c] ? 0 : uint8_t(cap);
    const std::size_t stride[3] = {1, std::size_t(dims_[0]), std::size_t(dims_[0]) * std::size_t(dims_[1])};
    for (int a = 0; a < 3; ++a) {
        // Lines along axis a: the other two axes enumerate their starts.
        const int b = (a + 1) % 3, e = (a + 2) % 3;
        const int n = dims_[a];
        const std::ptrdiff_t step = std::ptrdiff_t(stride[a]);
        // Lines are independent: slabs of them run on the pool's threads.
        constexpr int kChunks = 8;
        pool.parallel_for(kChunks, [&](std::size_t chunk, unsigned) {
            for (int j = int(chunk) * dims_[e] / kChunks; j < (int(chunk) + 1) * dims_[e] / kChunks; ++j)
                for (int i = 0; i < dims_[b]; ++i) {
                    const std::size_t base = std::size_t(i) * stride[b] + std::size_t(j) * stride[e];
                    const uint8_t* in = d.data() + base;
                    uint8_t* out = next.data() + base;
                    for (int at = 0; at < n; ++at) {
                        int best = in[at * step];
                        for (int t = 1; t < best; ++t) {
                            if (at - t >= 0) best = std::min(best, std::max(t, int(in[(at - t) * step])));
                            if (at + t < n) best = std::min(best, std::max(t, int(in[(at + t) * step])));
                        }
                        out[at * step] = uint8_t(best);
                    }
                }
        });
        d.swap(next);
    }
    // A cell at distance k: shells 0 .. k - 1 around it hold no point.
    empty_shells_ = std::move(d);
}

uint32_t GridIndex::nearest(const Eigen::Vector3d& q, double radius, double* dist2) const {
    if (sorted_.empty()) return kNone;
    double best = radius * radius;
    if (brute_force_) {
        uint32_t found = kNone;
        for (std::size_t k = 0; k < sorted_.size(); ++k) {
            const double d2 = (sorted_[k] - q).squaredNorm();
            if (d2 < best) best = d2, found = uint32_t(k);
        }
        if (found != kNone && dist2) *dist2 = best;
        return found;
    }
    // Queries far from the set (most of the limb search's) are answered by the bounding box.
    double outside2 = 0;
    for (int a = 0; a < 3; ++a) {
        const double below = lo_[a] - q[a], above = q[a] - hi_[a];
        if (below > 0) outside2 += below * below;
        if (above > 0) outside2 += above * above;
    }
    if (outside2 >= best) return kNone;
    int qc[3];
    double f[3];  // q in cell units
    for (int a = 0; a < 3; ++a) {
        f[a] = (q[a] - lo_[a]) * inverse_cell_;
        qc[a] = int(std::clamp(std::floor(f[a]), 0.0, double(dims_[a] - 1)));
    }
    // Distance (metres) along one axis from q (at f, in cell units) to the slab of cells c.
    auto axis_gap = [&](double fa, int c) { return (fa < c ? double(c) - fa : fa > c + 1 ? fa - double(c + 1) : 0.0) * cell_; };
    uint32_t found = kNone;
    const std::size_t nx = std::size_t(dims_[0]), nxy = nx * std::size_t(dims_[1]);
    auto scan = [&](std::size_t first_cell, std::size_t end_cell) {  // cells [first, end) of one row
        for (uint32_t k = start_[first_cell]; k < start_[end_cell]; ++k) {
            const double d2 = (sorted_[k] - q).squaredNorm();
            if (d2 < best) best = d2, found = k;
        }
    };
    // Shells of cells around q's cell (Chebyshev distance s), nearest first, clipped to the grid;
    // those index_empty_space() found empty are skipped. (q's cell is clamped to the grid, which
    // only brings it nearer every cell: the count holds for q.)
    int first = 0;
    if (!empty_shells_.empty())
        first = empty_shells_[std::size_t(qc[0]) + std::size_t(dims_[0]) * (std::size_t(qc[1]) + std::size_t(dims_[1]) * std::size_t(qc[2]))];
    for (int s = first;; ++s) {
        if (s > 0) {
            // Shell s lies beyond the faces of the box of the shells before it: stop once that is
            // farther than the best so far (or the grid has no cells beyond any face).
            double gap = std::numeric_limits<double>::infinity();
            for (int a = 0; a < 3; ++a) {
                if (qc[a] - s >= 0) gap = std::min(gap, (f[a] - double(qc[a] - s + 1)) * cell_);
                if (qc[a] + s < dims_[a]) gap = std::min(gap, (double(qc[a] + s) - f[a]) * cell_);
            }
            if (gap == std::numeric_limits<double>::infinity() || (gap > 0 && gap * gap >= best)) break;
        }
        const int x0 = std::max(qc[0] - s, 0), x1 = std::min(qc[0] + s, dims_[0] - 1);
        const int y0 = std::max(qc[1] - s, 0), y1 = std::min(qc[1] + s, dims_[1] - 1);
        const int z0 = std::max(qc[2] - s, 0), z1 = std::min(qc[2] + s, dims_[2] - 1);
        // Rows of cells farther from q than the best so far are skipped, and full rows are
        // clipped to the span the best distance still reaches.
        for (int z = z0; z <= z1; ++z) {
            const double gz = axis_gap(f[2], z), rz = best - gz * gz;
            if (rz <= 0) continue;
            const bool z_face = std::abs(z - qc[2]) == s;
            for (int y = y0; y <= y1; ++y) {
                const double gy = axis_gap(f[1], y), ryz = rz - gy * gy;
                if (ryz <= 0) continue;
                const std::size_t row = std::size_t(z) * nxy + std::size_t(y) * nx;
                if (z_face || std::abs(y - qc[1]) == s) {  // a whole row of the shell: contiguous
                    const double reach = std::sqrt(ryz) * inverse_cell_;
                    const int a = int(std::max(double(x0), std::floor(f[0] - reach))), b = int(std::min(double(x1), std::floor(f[0] + reach)));
                    if (a <= b) scan(row + std::size_t(a), row + std::size_t(b) + 1);
                } else {
                    const int a = qc[0] - s, b = qc[0] + s;
                    if (a >= 0 && axis_gap(f[0], a) * axis_gap(f[0], a) < ryz) scan(row + std::size_t(a), row + std::size_t(a) + 1);
                    if (s > 0 && b < dims_[0] && axis_gap(f[0], b) * axis_gap(f[0], b) < ryz) scan(row + std::size_t(b), row + std::size_t(b) + 1);
                }
            }
        }
    }
    if (found == kNone) return kNone;
    if (dist2) *dist2 = best;
    return original_[found];
}

}  // namespace ssc::fitting
