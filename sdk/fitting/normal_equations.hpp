// Accumulates the Gauss-Newton normal equations H = sum J_i^T J_i of many small residual blocks
// whose Jacobians touch few parameters.
//
// Why: adding each block to H entry by entry costs a scalar multiply-add per touched pair of
// columns and was the fitter's largest cost. Blocks with the same column set (every point
// skinned by the same joints) are stacked instead and multiplied once as a dense matrix product,
// which runs at several times the speed.
//
// Use: name each block's column set (column_set, cached by callers: a vertex keeps its set while
// the active parameters stay the same), reserve its rows, allocate, then fill the rows (from any
// threads, each block its own rows) and add the products to H.
#pragma once

#include "common/thread_pool.hpp"
#include "fitting/arrow_system.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace ssc::fitting {

class NormalEquations {
public:
    // Forgets every column set (their ids become invalid) and the rows.
    void clear();
    // Starts a new sum: drops the rows, keeps the column sets and their ids.
    void reset();

    // The id of a column set (sorted global parameter indices), added if new.
    uint32_t column_set(const std::vector<uint32_t>& cols);
    const std::vector<uint32_t>& columns(uint32_t set) const { return sets_[set].cols; }

    // Reserves `rows` rows on a column set; returns their first row, for rows() after allocate().
    std::size_t reserve(uint32_t set, uint32_t rows);
    // Makes room for every reservation of this sum. Contents are undefined until written.
    void allocate();
    // Row `row` of a column set: row-major, columns(set).size() wide. Each reserved row must be
    // written once; different rows may be written by different threads.
    double* rows(uint32_t set, std::size_t row) { return rows_.data() + sets_[set].row_offset + row * sets_[set].cols.size(); }

    // Adds the sum into the upper triangle of H (parameters x parameters). The products and their
    // sums into H run on the pool's threads; H receives them in a fixed order, so the sum does not
    // depend on the thread count.
    void add_to_upper(Eigen::MatrixXd& H, ThreadPool& pool);
    // The same into an arrow system's blocks (every column set within the arrow: shape columns and
    // one frame's). Each block receives the sets in order on one thread: the same sums for any
    // thread count.
    void add_to_upper(ArrowSystem& H, ThreadPool& pool);

private:
    void multiply(ThreadPool& pool);  // each set's product, its upper triangle
    struct Set {
        std::vector<uint32_t> cols;
        std::size_t reserved = 0;   // rows
        std::size_t row_offset = 0, product_offset = 0;  // into rows_ and products_ (allocate())
    };
    struct Hash {
        std::size_t operator()(const std::vector<uint32_t>& v) const;
    };
    std::vector<Set> sets_;
    std::vector<double> rows_;      // each reserved set's rows: row-major, cols.size() wide
    std::vector<double> products_;  // each reserved set's product: column-major, upper triangle
    std::unordered_map<std::vector<uint32_t>, uint32_t, Hash> index_;
};

}  // namespace ssc::fitting
