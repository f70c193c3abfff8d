// Accumulates the Gauss-Newton normal equations H = sum J_i^T J_i of many small residual blocks
// whose Jacobians touch few parameters.
//
// Why: adding each block to H entry by entry costs a scalar multiply-add per touched pair of
// columns and was the fitter's largest cost. Blocks with the same column set (every point
// skinned by the same joints) are stacked instead and multiplied once as a dense matrix product,
// which runs at several times the speed.
#pragma once

#include "common/thread_pool.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace ssc::fitting {

class NormalEquations {
public:
    // Starts a new sum (buffers are kept for reuse).
    void reset();

    // Adds J^T J for a block of `rows` residual rows (row-major, rows x cols.size()) whose
    // columns are the sorted global parameter indices `cols`.
    void add(const std::vector<uint32_t>& cols, const double* J, uint32_t rows);

    // Adds the accumulated sum into the upper triangle of H (parameters x parameters). The
    // blocks' products run on the pool's threads; H receives them in a fixed order, so the sum
    // does not depend on the thread count.
    void add_to_upper(Eigen::MatrixXd& H, ThreadPool& pool);

private:
    struct Bucket {
        std::vector<uint32_t> cols;
        std::vector<double> rows;  // row-major, cols.size() wide
    };
    struct Hash {
        std::size_t operator()(const std::vector<uint32_t>& v) const;
    };
    std::vector<Bucket> buckets_;
    std::size_t used_ = 0;  // buckets_[0, used_) belong to the current sum
    std::unordered_map<std::vector<uint32_t>, std::size_t, Hash> index_;
    std::vector<Eigen::MatrixXd> products_;  // per bucket
};

}  // namespace ssc::fitting
