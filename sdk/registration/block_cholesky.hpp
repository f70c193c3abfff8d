// A sparse Cholesky factorisation for symmetric positive definite matrices made of 4x4 blocks, as
// the non-rigid deformation's normal equations are (one block row per template vertex).
//
// Why our own: Eigen's SimplicialLLT works entry by entry and took 370 ms per factorisation of the
// default template's system (53,520 unknowns, 4.4 million entries in its factor); CHOLMOD's
// supernodal factorisation is faster but GPL-licensed, which a permissive library cannot ship.
// Working on 4x4 blocks (fixed-size Eigen products) over the vertex graph, with the graph
// ordered by approximate minimum degree (Eigen's AMD), does the same arithmetic several times
// faster. The algorithm is the up-looking one of Davis, "Direct Methods for Sparse Linear
// Systems" (cs_chol), on blocks. Two groups of independent subtrees of the elimination tree run on
// two threads (the default template's: 69 % of the work, the rest its top); the diagonal blocks
// are kept inverted so every step is a fixed-size product. Nested dissection (METIS) was tried as
// the ordering for better-balanced trees: 15 % more fill than AMD, slower on two cores.
#pragma once

#include "common/thread_pool.hpp"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstdint>
#include <functional>
#include <vector>

namespace ssc::registration {

class BlockCholesky4 {
public:
    // The structure of K (4n x 4n, both triangles stored, every 4x4 diagonal block present): which
    // blocks are nonzero. Orders the blocks and allocates the factor.
    void analyze(const Eigen::SparseMatrix<double>& K);
    // Factorises K (same structure as analysed). Returns false when K is not positive definite.
    // With a pool, independent subtrees of the elimination tree are factorised on its threads; the
    // factor is the same with or without one, and whatever the pool's size.
    bool factorize(const Eigen::SparseMatrix<double>& K, ThreadPool* pool = nullptr);
    // Solves K X = B for the last factorisation (B: 4n rows); the pool as for factorize.
    Eigen::MatrixX3d solve(const Eigen::MatrixX3d& B, ThreadPool* pool = nullptr) const;
    // How many groups of rows may run at once (0: the structure gave no balanced split).
    std::size_t parallel_parts() const { return parts_.size(); }

private:
    using Block = Eigen::Matrix4d;
    struct Workspace {  // one per part of the tree: the row being formed (zero between rows), its pattern
        std::vector<Block, Eigen::aligned_allocator<Block>> x;
        std::vector<uint32_t> mark, stack, path;
        explicit Workspace(uint32_t n) : x(n, Block::Zero()), mark(n, UINT32_MAX), stack(n), path(n) {}
    };
    void split_tree(const std::vector<double>& row_work);
    // fn(part) for every part, on the pool's threads when it has several (fn must not throw).
    void for_each_part(ThreadPool* pool, const std::function<void(std::size_t part)>& fn) const;
    bool factor_row(uint32_t k, Workspace& w);
    uint32_t n_ = 0;                                 // block rows
    std::vector<uint32_t> new_of_old_, old_of_new_;  // the ordering
    // K's blocks in the new order, upper triangle by column (rows <= column, the diagonal last).
    std::vector<std::size_t> upper_ptr_;
    std::vector<uint32_t> upper_row_;
    std::vector<Block, Eigen::aligned_allocator<Block>> upper_;
    std::vector<int64_t> destination_;  // per stored entry of K: where it goes in upper_ (as doubles), or -1
    std::vector<int32_t> parent_;           // elimination tree
    // The factor L by columns: the diagonal block, then the blocks below it in row order.
    std::vector<std::size_t> l_ptr_;
    std::vector<uint32_t> l_row_;
    std::vector<Block, Eigen::aligned_allocator<Block>> l_value_;
    std::vector<Block, Eigen::aligned_allocator<Block>> inverse_diagonal_;  // L(k, k)^-1
    std::vector<std::size_t> fill_;  // during factorize: the next free slot of each column
    std::vector<Workspace> workspaces_;  // kept between factorisations
    // The rows in kParts groups of whole subtrees of the elimination tree (balanced by work) and
    // the rest (the tree's top), each in increasing order. A row's factor row and its solve
    // steps read and write only its subtree's columns and the top's, so the groups can run at
    // once; the top follows. Fixed by the structure, so results do not depend on threads.
    std::vector<std::vector<uint32_t>> parts_;
    std::vector<uint32_t> top_;
    std::vector<int32_t> top_slot_;  // per row: its index in top_, or -1
};

}  // namespace ssc::registration
