#include "fitting/normal_equations.hpp"

#include "synthesis/cpu.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#include <immintrin.h>
#define SSC_PRODUCT_AVX2 1
#endif

namespace ssc::fitting {

namespace {

#ifdef SSC_PRODUCT_AVX2
SSC_TARGET_AVX2_BEGIN
// The upper triangle of R^T R (R: `rows` x n, row-major) into P (n x n, column-major):
// P(i, c), i <= c, = sum over r of R(r, i) R(r, c), fused multiply-adds in row order.
// Register tiles of 2 columns x 16 rows of P (8 accumulators: what two FMA ports need in flight),
// over tiles of 32 rows of R that stay in L1. Narrower tiles and a scalar loop finish each column.
// Without AVX2 Eigen's product serves (SSE2): its sums round differently in the last bits.
void upper_product_avx2(const double* R, std::size_t rows, std::size_t n, double* P) {
    constexpr std::size_t kRowTile = 32;
    // Column c is summed to row c + 1 (pairs of columns share tiles): zero that far.
    for (std::size_t c = 0; c < n; ++c) std::memset(P + c * n, 0, sizeof(double) * std::min(n, c + 2));
    for (std::size_t r0 = 0; r0 < rows; r0 += kRowTile) {
        const std::size_t r1 = std::min(rows, r0 + kRowTile);
        for (std::size_t c = 0; c < n; c += 2) {
            const bool pair = c + 1 < n;
            const std::size_t c1 = pair ? c + 1 : c;
            double* p0 = P + c * n;
            double* p1 = P + c1 * n;
            const std::size_t height = c1 + 1;  // entries of column c1 on or above the diagonal
            std::size_t i = 0;
            for (; i + 16 <= height; i += 16) {
                __m256d a[2][4];
                for (int k = 0; k < 4; ++k) a[0][k] = _mm256_loadu_pd(p0 + i + 4 * k), a[1][k] = _mm256_loadu_pd(p1 + i + 4 * k);
                for (std::size_t r = r0; r < r1; ++r) {
                    const double* row = R + r * n;
                    const __m256d b0 = _mm256_broadcast_sd(row + c), b1 = _mm256_broadcast_sd(row + c1);
                    for (int k = 0; k < 4; ++k) {
                        const __m256d x = _mm256_loadu_pd(row + i + 4 * k);
                        a[0][k] = _mm256_fmadd_pd(b0, x, a[0][k]);
                        a[1][k] = _mm256_fmadd_pd(b1, x, a[1][k]);
                    }
                }
                for (int k = 0; k < 4; ++k) _mm256_storeu_pd(p0 + i + 4 * k, a[0][k]), _mm256_storeu_pd(p1 + i + 4 * k, a[1][k]);
            }
            for (; i + 4 <= height; i += 4) {
                __m256d a0 = _mm256_loadu_pd(p0 + i), a1 = _mm256_loadu_pd(p1 + i);
                for (std::size_t r = r0; r < r1; ++r) {
                    const double* row = R + r * n;
                    const __m256d x = _mm256_loadu_pd(row + i);
                    a0 = _mm256_fmadd_pd(_mm256_broadcast_sd(row + c), x, a0);
                    a1 = _mm256_fmadd_pd(_mm256_broadcast_sd(row + c1), x, a1);
                }
                _mm256_storeu_pd(p0 + i, a0), _mm256_storeu_pd(p1 + i, a1);
            }
            for (; i < height; ++i) {
                double a0 = p0[i], a1 = p1[i];
                for (std::size_t r = r0; r < r1; ++r) {
                    const double* row = R + r * n;
                    a0 = std::fma(row[c], row[i], a0);
                    a1 = std::fma(row[c1], row[i], a1);
                }
                p0[i] = a0, p1[i] = a1;
            }
        }
    }
}
SSC_TARGET_END
#endif

}  // namespace

std::size_t NormalEquations::Hash::operator()(const std::vector<uint32_t>& v) const {
    std::size_t h = v.size();
    for (uint32_t c : v) h = h * 1000003u ^ c;
    return h;
}

void NormalEquations::clear() {
    sets_.clear();
    index_.clear();
}

void NormalEquations::reset() {
    for (Set& s : sets_) s.reserved = 0;
}

uint32_t NormalEquations::column_set(const std::vector<uint32_t>& cols) {
    auto [it, inserted] = index_.try_emplace(cols, uint32_t(sets_.size()));
    if (inserted) sets_.emplace_back().cols = cols;
    return it->second;
}

std::size_t NormalEquations::reserve(uint32_t set, uint32_t rows) {
    const std::size_t first = sets_[set].reserved;
    sets_[set].reserved += rows;
    return first;
}

void NormalEquations::allocate() {
    for (Set& s : sets_) s.rows.resize(s.reserved * s.cols.size());
}

void NormalEquations::add_to_upper(Eigen::MatrixXd& H, ThreadPool& pool) {
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    pool.parallel_for(sets_.size(), [&](std::size_t b, unsigned) {
        Set& s = sets_[b];
        if (s.reserved == 0) return;
        const auto n = Eigen::Index(s.cols.size());
        // Only the upper triangle is written and read: the rest stays as is.
        s.product.resize(n, n);
#ifdef SSC_PRODUCT_AVX2
        if (kernels::active_isa() != kernels::Isa::Baseline)
            return upper_product_avx2(s.rows.data(), s.reserved, std::size_t(n), s.product.data());
#endif
        s.product.triangularView<Eigen::Upper>().setZero();
        const Eigen::Map<const RowMajor> R(s.rows.data(), Eigen::Index(s.reserved), n);
        s.product.selfadjointView<Eigen::Upper>().rankUpdate(R.transpose());
    });
    // The products go into H on the pool's threads too, each thread a band of H's columns (every
    // set in order, so each entry sums the same terms in the same order for any thread count).
    // Bands are equal shares of the upper triangle: column c holds c + 1 entries.
    constexpr std::size_t kBands = 8;
    const double P = double(H.cols());
    auto band_start = [&](std::size_t b) { return uint32_t(std::lround(P * std::sqrt(double(b) / kBands))); };
    pool.parallel_for(kBands, [&](std::size_t b, unsigned) {
        const uint32_t lo = band_start(b), hi = band_start(b + 1);
        for (const Set& s : sets_) {
            if (s.reserved == 0) continue;
            // cols is sorted, so the upper triangle of the block lands in H's upper triangle.
            const auto first = std::lower_bound(s.cols.begin(), s.cols.end(), lo) - s.cols.begin();
            for (auto c = first; c < Eigen::Index(s.cols.size()) && s.cols[std::size_t(c)] < hi; ++c) {
                double* column = H.col(s.cols[std::size_t(c)]).data();
                for (Eigen::Index r = 0; r <= c; ++r) column[s.cols[std::size_t(r)]] += s.product(r, c);
            }
        }
    });
}

}  // namespace ssc::fitting
