// Shape stage: rest = mean + sum_k (c_k * step_k) * q_k over the 16-bit basis.
//
// Every output value is accumulated as acc = fma(c_k * step_k, q_k, acc) for k = 0, 1, ... in
// that order, whatever the blocking; so one body and a batch give bit-identical results.
//
// Cost model: the basis is 4 MB for the default-size model, more than L2, so one body is bound by
// the bandwidth of streaming it from L3. The panel layout (model.hpp) makes that one sequential
// stream. A batch tiles bodies so each basis chunk, once loaded, feeds up to 8 bodies'
// accumulators held in registers, which makes it compute-bound instead.
#include "kernels.hpp"
#include "model.hpp"

#include <algorithm>
#include <cmath>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define SSC_SHAPE_AVX2 1
#endif

namespace ssc::kernels {
namespace {

constexpr std::size_t kChunk = Model::kChunk;

#ifdef SSC_SHAPE_AVX2
// G bodies x C chunks (8 rows each) starting at chunk `chunk`: G * C independent accumulators
// hide the FMA latency.
template <int G, int C>
void tile(const Model& m, std::size_t chunk, const float* const* scaled, float* const* rest) {
    const uint32_t K = m.component_count();
    const std::size_t r = chunk * kChunk;
    const int16_t* panel = m.basis_panels() + chunk * K * kChunk;
    const float* sg[G];
    __m256 acc[G][C];
    for (int g = 0; g < G; ++g) sg[g] = scaled[g];
    for (int c = 0; c < C; ++c) {
        const __m256 mean = _mm256_loadu_ps(m.mean_planar() + r + kChunk * c);
        for (int g = 0; g < G; ++g) acc[g][c] = mean;
    }
    for (uint32_t k = 0; k < K; ++k) {
        __m256 b[C];
        for (int c = 0; c < C; ++c) {
            const auto* p = reinterpret_cast<const __m128i*>(panel + (c * K + k) * kChunk);
            b[c] = _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(_mm_loadu_si128(p)));
        }
        for (int g = 0; g < G; ++g) {
            const __m256 cg = _mm256_broadcast_ss(sg[g] + k);
            for (int c = 0; c < C; ++c) acc[g][c] = _mm256_fmadd_ps(cg, b[c], acc[g][c]);
        }
    }
    for (int g = 0; g < G; ++g)
        for (int c = 0; c < C; ++c) _mm256_storeu_ps(rest[g] + r + kChunk * c, acc[g][c]);
}

template <int G, int C>
void tiles(const Model& m, const float* const* scaled, float* const* rest) {
    const std::size_t chunks = m.padded_rows() / kChunk;
    std::size_t c = 0;
    for (; c + C <= chunks; c += C) tile<G, C>(m, c, scaled, rest);
    for (; c < chunks; ++c) tile<G, 1>(m, c, scaled, rest);
}
#else
void tiles_scalar(const Model& m, std::size_t count, const float* const* scaled, float* const* rest) {
    const uint32_t K = m.component_count();
    for (std::size_t g = 0; g < count; ++g)
        for (std::size_t r = 0; r < m.padded_rows(); ++r) {
            const int16_t* panel = m.basis_panels() + (r / kChunk) * K * kChunk + r % kChunk;
            float acc = m.mean_planar()[r];
            for (uint32_t k = 0; k < K; ++k) acc = std::fma(scaled[g][k], float(panel[k * kChunk]), acc);
            rest[g][r] = acc;
        }
}
#endif

}  // namespace

void scale_coefficients(const Model& m, const float* coeffs, float* scaled) {
    for (uint32_t k = 0; k < m.component_count(); ++k) scaled[k] = coeffs[k] * m.basis_step()[k];
}

void shape(const Model& m, std::size_t count, const float* const* scaled, float* const* rest, float* const* joints) {
#ifdef SSC_SHAPE_AVX2
    // Bodies in groups of 8, 4, 2, 1; each group is one pass over the basis.
    for (std::size_t g = 0; g < count;) {
        const std::size_t left = count - g;
        if (left >= 8) tiles<8, 1>(m, scaled + g, rest + g), g += 8;
        else if (left >= 4) tiles<4, 2>(m, scaled + g, rest + g), g += 4;
        else if (left >= 2) tiles<2, 4>(m, scaled + g, rest + g), g += 2;
        else tiles<1, 8>(m, scaled + g, rest + g), g += 1;
    }
#else
    tiles_scalar(m, count, scaled, rest);
#endif
    const uint32_t J = m.joint_count(), K = m.component_count();
    for (std::size_t g = 0; g < count; ++g) {
        float* out = joints[g];
        for (uint32_t i = 0; i < 3 * J; ++i) {
            float acc = m.joint_mean()[i];
            for (uint32_t k = 0; k < K; ++k) acc = std::fma(scaled[g][k], m.joint_basis()[std::size_t(k) * 3 * J + i], acc);
            out[i] = acc;
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
