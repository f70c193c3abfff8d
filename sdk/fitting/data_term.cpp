#include "fitting/data_term.hpp"

#include "fitting/robust.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <cmath>

namespace ssc::fitting {

namespace {

using Eigen::VectorXd;

// The groups' rows summed at once: 32 MB. One frame's fit (about 6,000 groups of 3 rows, 80
// columns or fewer) stays within one batch; many frames are summed a few at a time.
constexpr std::size_t kBatchDoubles = std::size_t(4) << 20;

bool single_vertex(const Block& b) { return b.point->weight[1] == 0 && b.point->weight[2] == 0; }

// R with R^T R = W for a group's summed weight (symmetric positive definite: every term has a
// point-to-point part): Cholesky, or the eigen-decomposition should rounding say otherwise.
Matrix3d weight_root(const Matrix3d& W) {
    const Eigen::LLT<Matrix3d> llt(W);
    if (llt.info() == Eigen::Success) return llt.matrixU();
    const Eigen::SelfAdjointEigenSolver<Matrix3d> es(W);
    return es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
}

}  // namespace

DataTerm::DataTerm(uint32_t K, uint32_t B, uint32_t F, uint32_t V) : K_(K), B_(B), F_(F), V_(V) {}

void DataTerm::set_blocks(std::vector<Block> blocks) {
    blocks_ = std::move(blocks);
    group_blocks();
}

// Groups follow their first block's order, members the blocks' order.
void DataTerm::group_blocks() {
    groups_.clear();
    group_of_.resize(blocks_.size());
    if (vertex_group_.size() != std::size_t(F_) * V_) vertex_group_.assign(std::size_t(F_) * V_, kNoSet);
    for (std::size_t i = 0; i < blocks_.size(); ++i) {
        const Block& b = blocks_[i];
        uint32_t* slot = single_vertex(b) ? &vertex_group_[std::size_t(b.frame) * V_ + b.point->vertex[0]] : nullptr;
        if (!slot || *slot == kNoSet) {
            if (slot) *slot = uint32_t(groups_.size());
            groups_.push_back({0, 0, 0, 0});
        }
        group_of_[i] = slot ? *slot : uint32_t(groups_.size() - 1);
        ++groups_[group_of_[i]].count;
    }
    uint32_t next = 0;
    for (Group& gr : groups_) gr.first = next, next += gr.count, gr.count = 0;
    members_.resize(blocks_.size());
    for (std::size_t i = 0; i < blocks_.size(); ++i) {
        Group& gr = groups_[group_of_[i]];
        members_[gr.first + gr.count++] = uint32_t(i);
    }
    for (const Block& b : blocks_)  // leave the map empty for the next call
        if (single_vertex(b)) vertex_group_[std::size_t(b.frame) * V_ + b.point->vertex[0]] = kNoSet;
}

// The column set of a block's Jacobian (active columns only), cached per frame and vertex for
// single-vertex points.
uint32_t DataTerm::column_set(const std::vector<Kinematics>& kin, const Block& b) {
    const bool single = single_vertex(b);
    uint32_t& cached = vertex_set_[b.frame][b.point->vertex[0]];
    if (single && cached != kNoSet) return cached;
    kin[b.frame].nonzeros(*b.point, nonzeros_);
    set_columns_.clear();
    for (uint32_t c : nonzeros_)
        if (set_active_[c]) set_columns_.push_back(column(b.frame, c));
    const uint32_t set = normal_.column_set(set_columns_);
    if (single) cached = set;
    return set;
}

double DataTerm::evaluate(const std::vector<Kinematics>& kin, const std::vector<uint8_t>& active, double gm_scale,
                          ArrowSystem* H, VectorXd* g, ThreadPool& pool) {
    const uint32_t P = K_ + F_ * B_, PL = K_ + B_;
    if (active != set_active_) {  // column sets follow the active parameters
        normal_.clear();
        set_active_ = active;
        vertex_set_.assign(F_, std::vector<uint32_t>(V_, kNoSet));
    }
    constexpr std::size_t kChunks = 8;
    double chunk_cost[kChunks] = {};
    if (H) {
        H->reset(K_, B_, F_);
        g->setZero(P);
        touched_.assign(P, 0);
        chunk_g_.assign(kChunks, VectorXd::Zero(P));
    }
    if (jacobian_scratch_.size() != pool.size() || jacobian_scratch_[0].size() != 3 * std::size_t(PL))
        jacobian_scratch_.assign(pool.size(), std::vector<double>(3 * std::size_t(PL), 0.0));
    // With H, the groups' rows are summed in batches of consecutive groups (kBatchDoubles of rows
    // each; groups follow the frames): a fit of many frames needs the memory of a few.
    for (std::size_t begin = 0, end = 0; begin < groups_.size(); begin = end) {
        end = groups_.size();
        if (H) {
            normal_.reset();
            std::size_t doubles = 0;
            for (end = begin; end < groups_.size() && doubles < kBatchDoubles; ++end) {
                Group& gr = groups_[end];
                gr.set = column_set(kin, blocks_[members_[gr.first]]);
                gr.row = normal_.reserve(gr.set, 3);
                if (gr.row == 0)
                    for (uint32_t c : normal_.columns(gr.set)) touched_[c] = 1;
                doubles += 3 * normal_.columns(gr.set).size();
            }
            normal_.allocate();
        }
        const std::size_t n_groups = end - begin;
        pool.parallel_for(kChunks, [&](std::size_t c, unsigned worker) {
            double* J3 = jacobian_scratch_[worker].data();
            double sum = 0;
            for (std::size_t gi = begin + c * n_groups / kChunks; gi < begin + (c + 1) * n_groups / kChunks; ++gi) {
                const Group& gr = groups_[gi];
                const Block& first = blocks_[members_[gr.first]];
                const Kinematics& k = kin[first.frame];
                // With H the Jacobian (of the point) comes first: it computes the point on the way.
                const Vector3d x = H ? k.point_jacobian(*first.point, J3, active.data()) : k.point(*first.point);
                // Each term's Gauss-Newton weight on the point (s^2 L^T L, e = s (x - target)) and
                // gradient factor (s m) add up over the group.
                Matrix3d W = Matrix3d::Zero();
                Vector3d m = Vector3d::Zero();
                for (uint32_t t = gr.first; t < gr.first + gr.count; ++t) {
                    const Block& b = blocks_[members_[t]];
                    const Vector3d e = b.scale * (x - *b.target);
                    Matrix3d L;
                    Vector3d mb;
                    if (b.normal) {
                        const PointPlaneTerm term = point_plane(e, *b.normal, gm_scale, H != nullptr);
                        sum += term.cost;
                        L = term.L, mb = term.m;
                    } else {
                        const Robust rb = huber(e.norm(), kHuber);
                        sum += rb.cost;
                        L = std::sqrt(rb.weight) * Matrix3d::Identity(), mb = rb.weight * e;
                    }
                    if (!H) continue;
                    W.noalias() += (b.scale * b.scale) * (L.transpose() * L);
                    m += b.scale * mb;
                }
                if (!H) continue;
                // Three rows R J with R^T R = W, on the group's column set, and J^T m into g.
                const Matrix3d R = weight_root(W);
                const std::vector<uint32_t>& cols = normal_.columns(gr.set);
                const std::size_t n = cols.size();
                double* rows = normal_.rows(gr.set, gr.row);
                VectorXd& gc = chunk_g_[c];
                for (std::size_t a = 0; a < n; ++a) {
                    const uint32_t l = cols[a] < K_ ? cols[a] : cols[a] - first.frame * B_;  // local column
                    const Vector3d j(J3[l], J3[PL + l], J3[2 * std::size_t(PL) + l]);
                    const Vector3d rj = R * j;
                    rows[a] = rj[0], rows[n + a] = rj[1], rows[2 * n + a] = rj[2];
                    gc[cols[a]] += j.dot(m);
                    J3[l] = J3[PL + l] = J3[2 * std::size_t(PL) + l] = 0;
                }
                // Translation and scale are written whether active or not.
                for (uint32_t l = PL - 4; l < PL; ++l) J3[l] = J3[PL + l] = J3[2 * std::size_t(PL) + l] = 0;
            }
            chunk_cost[c] += sum;
        });
        if (H) normal_.add_to_upper(*H, pool);
    }
    double cost = 0;
    for (std::size_t c = 0; c < kChunks; ++c) {
        cost += chunk_cost[c];
        if (H) *g += chunk_g_[c];
    }
    return cost;
}

}  // namespace ssc::fitting
