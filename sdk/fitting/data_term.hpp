// The fit's data energy: landmarks (Huber on the distance) and scan correspondences
// (point-to-plane where normals exist, Geman-McClure loss: robust.hpp), with the Gauss-Newton normal
// equations of their linearisation summed in blocks (normal_equations.hpp) into the arrow of
// shape and per-frame columns (arrow_system.hpp).
#pragma once

#include "common/thread_pool.hpp"
#include "fitting/arrow_system.hpp"
#include "fitting/kinematics.hpp"
#include "fitting/normal_equations.hpp"

#include <Eigen/Core>

#include <vector>

namespace ssc::fitting {

// Landmarks beyond this many sigmas count linearly (Huber): a misplaced landmark pulls, but boundedly.
constexpr double kHuber = 2.0;

// One residual block of the data: a landmark (Huber on the distance) or a correspondence
// (point-to-plane). scale = sqrt(weight) / sigma. Pointees are the caller's and must outlive the
// blocks.
struct Block {
    uint32_t frame;
    const SurfacePoint* point;
    const Vector3d* target;
    const Vector3d* normal;  // null for a landmark
    double scale;
};

// Parameters: K shape columns shared by F frames of B columns each (kinematics.hpp's layout after
// the shape). Not thread-safe: scratch buffers; its sums use the pool's threads.
class DataTerm {
public:
    DataTerm(uint32_t K, uint32_t B, uint32_t F, uint32_t V);

    // The residual blocks, until the next call (correspondences change every iteration; the trial
    // steps of one reuse them).
    void set_blocks(std::vector<Block> blocks);

    // Cost of the blocks with the kinematics of each frame (updated to the state); with H and g
    // (both reset here), the normal equations of the linearisation on the active parameters
    // (per local parameter: K + B flags). gm_scale: the Geman-McClure scale in sigmas. The blocks
    // run in fixed chunks whose sums are merged in order: the same result for any thread count.
    double evaluate(const std::vector<Kinematics>& kin, const std::vector<uint8_t>& active, double gm_scale, ArrowSystem* H,
                    Eigen::VectorXd* g, ThreadPool& pool);

    // Per global column: whether some data row reached it in the last evaluate() with H.
    const std::vector<uint8_t>& touched() const { return touched_; }

private:
    void group_blocks();
    uint32_t column_set(const std::vector<Kinematics>& kin, const Block& b);
    uint32_t column(uint32_t f, uint32_t local) const { return local < K_ ? local : K_ + f * B_ + (local - K_); }

    static constexpr uint32_t kNoSet = 0xFFFFFFFFu;
    uint32_t K_, B_, F_, V_;
    NormalEquations normal_;  // data blocks of the H being built
    std::vector<Block> blocks_;
    // The correspondences of one model vertex in one frame form one group (a third of them share a
    // vertex with another), every other block its own: a group's Jacobian is computed once and its
    // terms' weights add up into one 3-row block.
    struct Group {
        uint32_t first, count;  // its blocks: members_[first, first + count)
        uint32_t set;
        std::size_t row;
    };
    std::vector<Group> groups_;
    std::vector<uint32_t> members_, group_of_;       // group_blocks() output and scratch
    std::vector<uint32_t> vertex_group_;             // per frame and vertex: its group in the current call, or kNoSet
    std::vector<uint8_t> set_active_;                // the active local parameters the column sets were made for
    std::vector<std::vector<uint32_t>> vertex_set_;  // per frame and vertex: its column set, or kNoSet
    std::vector<uint32_t> nonzeros_, set_columns_;   // column_set() scratch
    std::vector<Eigen::VectorXd> chunk_g_;           // evaluate(): per chunk gradient
    std::vector<std::vector<double>> jacobian_scratch_;  // evaluate(): per worker, 3 rows of local columns, kept zero
    std::vector<uint8_t> touched_;
};

}  // namespace ssc::fitting
