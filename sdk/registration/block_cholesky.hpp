// A sparse Cholesky factorisation for symmetric positive definite matrices made of 4x4 blocks, as
// the non-rigid deformation's normal equations are (one block row per template vertex).
//
// Why our own: Eigen's SimplicialLLT works entry by entry and took 370 ms per factorisation of the
// default template's system (53,520 unknowns, 4.4 million entries in its factor); CHOLMOD's
// supernodal factorisation is faster but GPL-licensed, which a permissive library cannot ship.
// Working on 4x4 blocks (fixed-size Eigen products) over the vertex graph, with the graph
// ordered by approximate minimum degree (Eigen's AMD), does the same arithmetic several times
// faster. The algorithm is the up-looking one of Davis, "Direct Methods for Sparse Linear
// Systems" (cs_chol), on blocks.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstdint>
#include <vector>

namespace ssc::registration {

class BlockCholesky4 {
public:
    // The structure of K (4n x 4n, both triangles stored, every 4x4 diagonal block present): which
    // blocks are nonzero. Orders the blocks and allocates the factor.
    void analyze(const Eigen::SparseMatrix<double>& K);
    // Factorises K (same structure as analysed). Returns false when K is not positive definite.
    bool factorize(const Eigen::SparseMatrix<double>& K);
    // Solves K X = B for the last factorisation (B: 4n rows).
    Eigen::MatrixX3d solve(const Eigen::MatrixX3d& B) const;

private:
    using Block = Eigen::Matrix4d;
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
    std::vector<Block, Eigen::aligned_allocator<Block>> diagonal_;  // L(k, k)
};

}  // namespace ssc::registration
