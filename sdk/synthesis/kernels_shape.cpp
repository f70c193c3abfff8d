// Shape stage: rest = mean + sum_k (c_k * step_k) * q_k over 16-bit basis rows.
// The basis is 4 MB for the default-size model, larger than L2, so one body is bound by memory
// bandwidth. Rows are walked in blocks small enough for L1 and every body of a batch is served
// from the block while it is hot. Four components per pass keep the accumulator traffic low.
#include "kernels.hpp"
#include "model.hpp"

#include <algorithm>

namespace ssc::kernels {
namespace {

constexpr std::size_t kBlock = 1024;

// One row block for one body: the same arithmetic in the same order whatever the batch size.
inline void accumulate(float* __restrict out, const int16_t* __restrict q, std::size_t rows, std::size_t n,
                       const float* coeffs, const float* step, uint32_t K) {
    uint32_t k = 0;
    for (; k + 4 <= K; k += 4) {
        const int16_t* __restrict p0 = q + k * rows;
        const int16_t* __restrict p1 = p0 + rows;
        const int16_t* __restrict p2 = p1 + rows;
        const int16_t* __restrict p3 = p2 + rows;
        const float c0 = coeffs[k] * step[k], c1 = coeffs[k + 1] * step[k + 1];
        const float c2 = coeffs[k + 2] * step[k + 2], c3 = coeffs[k + 3] * step[k + 3];
        for (std::size_t r = 0; r < n; ++r)
            out[r] += (c0 * float(p0[r]) + c1 * float(p1[r])) + (c2 * float(p2[r]) + c3 * float(p3[r]));
    }
    for (; k < K; ++k) {
        const int16_t* __restrict p = q + k * rows;
        const float c = coeffs[k] * step[k];
        for (std::size_t r = 0; r < n; ++r) out[r] += c * float(p[r]);
    }
}

}  // namespace

void shape(const Model& m, std::size_t count, const float* const* coeffs, float* const* rest, float* const* joints) {
    const uint32_t K = m.component_count(), J = m.joint_count();
    const std::size_t rows = 3ull * m.vertex_count();

    for (std::size_t r0 = 0; r0 < rows; r0 += kBlock) {
        const std::size_t n = std::min(kBlock, rows - r0);
        for (std::size_t g = 0; g < count; ++g) {
            float* out = rest[g] + r0;
            std::copy(m.mean_planar() + r0, m.mean_planar() + r0 + n, out);
            accumulate(out, m.basis_q() + r0, rows, n, coeffs[g], m.basis_step(), K);
        }
    }
    for (std::size_t g = 0; g < count; ++g) {
        float* out = joints[g];
        std::copy(m.joint_mean(), m.joint_mean() + 3 * J, out);
        for (uint32_t k = 0; k < K; ++k) {
            const float c = coeffs[g][k];
            if (c == 0.f) continue;
            const float* b = m.joint_basis() + std::size_t(k) * 3 * J;
            for (uint32_t i = 0; i < 3 * J; ++i) out[i] += c * b[i];
        }
    }
}

void planar_to_xyz(const float* planar, uint32_t n, float* out, std::size_t stride) {
    auto* base = reinterpret_cast<unsigned char*>(out);
    for (uint32_t v = 0; v < n; ++v) {
        float* p = reinterpret_cast<float*>(base + v * stride);
        p[0] = planar[v];
        p[1] = planar[n + v];
        p[2] = planar[2 * n + v];
    }
}

}  // namespace ssc::kernels
