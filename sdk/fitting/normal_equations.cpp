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
// Columns c and c1 of P, T vectors of 4 entries from entry i, summed over rows [r0, r1) of R: 2T
// accumulators held in registers. The last vector loads and stores only the lanes in `last`
// (entries past n are never touched).
template <int T>
inline void product_tile(const double* R, std::size_t r0, std::size_t r1, std::size_t n, std::size_t c, std::size_t c1,
                         std::size_t i, __m256i last, double* p0, double* p1) {
    const __m256i all = _mm256_set1_epi64x(-1);
    __m256d a[2][T];
    for (int k = 0; k < T; ++k) {
        const __m256i m = k + 1 < T ? all : last;
        a[0][k] = _mm256_maskload_pd(p0 + i + 4 * k, m);
        a[1][k] = _mm256_maskload_pd(p1 + i + 4 * k, m);
    }
    for (std::size_t r = r0; r < r1; ++r) {
        const double* row = R + r * n;
        const __m256d b0 = _mm256_broadcast_sd(row + c), b1 = _mm256_broadcast_sd(row + c1);
        for (int k = 0; k < T; ++k) {
            const __m256d x = k + 1 < T ? _mm256_loadu_pd(row + i + 4 * k) : _mm256_maskload_pd(row + i + 4 * k, last);
            a[0][k] = _mm256_fmadd_pd(b0, x, a[0][k]);
            a[1][k] = _mm256_fmadd_pd(b1, x, a[1][k]);
        }
    }
    for (int k = 0; k < T; ++k) {
        const __m256i m = k + 1 < T ? all : last;
        _mm256_maskstore_pd(p0 + i + 4 * k, m, a[0][k]);
        _mm256_maskstore_pd(p1 + i + 4 * k, m, a[1][k]);
    }
}

// The upper triangle of R^T R (R: `rows` x n, row-major) into P (n x n, column-major):
// P(i, c), i <= c, = sum over r of R(r, i) R(r, c), fused multiply-adds in row order. Columns go
// in pairs; each pair's entries down to the diagonal, rounded up to whole vectors (the extra
// entries lie below the diagonal, which is not read), in register tiles of up to 2 x 16, over
// tiles of 32 rows of R that stay in L1. Without AVX2, Eigen's product serves (SSE2): its sums
// round differently in the last bits.
void upper_product_avx2(const double* R, std::size_t rows, std::size_t n, double* P) {
    constexpr std::size_t kRowTile = 32;
    auto vectors = [](std::size_t c) { return (c + 2 + 3) / 4; };  // a pair from c: rows 0..c+1, whole vectors
    for (std::size_t c = 0; c < n; ++c) std::memset(P + c * n, 0, sizeof(double) * std::min(n, 4 * vectors(c - c % 2)));
    for (std::size_t r0 = 0; r0 < rows; r0 += kRowTile) {
        const std::size_t r1 = std::min(rows, r0 + kRowTile);
        for (std::size_t c = 0; c < n; c += 2) {
            const std::size_t c1 = c + 1 < n ? c + 1 : c;
            double* p0 = P + c * n;
            double* p1 = P + c1 * n;
            const std::size_t q = vectors(c);
            // Lanes of the pair's last vector that lie inside the column.
            const std::size_t lanes = std::min<std::size_t>(4, n - 4 * (q - 1));
            const __m256i last = _mm256_cmpgt_epi64(_mm256_set1_epi64x(int64_t(lanes)), _mm256_setr_epi64x(0, 1, 2, 3));
            const __m256i all = _mm256_set1_epi64x(-1);
            std::size_t v = 0;
            for (; v + 4 < q; v += 4) product_tile<4>(R, r0, r1, n, c, c1, 4 * v, all, p0, p1);
            switch (q - v) {
                case 4: product_tile<4>(R, r0, r1, n, c, c1, 4 * v, last, p0, p1); break;
                case 3: product_tile<3>(R, r0, r1, n, c, c1, 4 * v, last, p0, p1); break;
                case 2: product_tile<2>(R, r0, r1, n, c, c1, 4 * v, last, p0, p1); break;
                default: product_tile<1>(R, r0, r1, n, c, c1, 4 * v, last, p0, p1); break;
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
    // One buffer for the rows and one for the products of the sets reserved in this sum, reused
    // from sum to sum: a fit of many frames sums its frames in batches (solver.cpp) and the
    // memory is that of one batch.
    std::size_t rows = 0, products = 0;
    for (Set& s : sets_) {
        if (s.reserved == 0) continue;
        s.row_offset = rows, s.product_offset = products;
        rows += s.reserved * s.cols.size();
        products += s.cols.size() * s.cols.size();
    }
    rows_.resize(rows);
    products_.resize(products);
}

void NormalEquations::multiply(ThreadPool& pool) {
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    pool.parallel_for(sets_.size(), [&](std::size_t b, unsigned) {
        Set& s = sets_[b];
        if (s.reserved == 0) return;
        const auto n = Eigen::Index(s.cols.size());
        // Only the upper triangle is written and read: the rest stays as is.
        const double* rows = rows_.data() + s.row_offset;
        double* product = products_.data() + s.product_offset;
#ifdef SSC_PRODUCT_AVX2
        if (kernels::active_isa() != kernels::Isa::Baseline) return upper_product_avx2(rows, s.reserved, std::size_t(n), product);
#endif
        Eigen::Map<Eigen::MatrixXd> P(product, n, n);
        P.triangularView<Eigen::Upper>().setZero();
        const Eigen::Map<const RowMajor> R(rows, Eigen::Index(s.reserved), n);
        P.selfadjointView<Eigen::Upper>().rankUpdate(R.transpose());
    });
}

void NormalEquations::add_to_upper(ArrowSystem& H, ThreadPool& pool) {
    multiply(pool);
    const uint32_t K = H.shape_columns(), B = H.frame_columns();
    // Task 0 fills the shape block, task 1 + f frame f's band and block.
    pool.parallel_for(std::size_t(H.frames()) + 1, [&](std::size_t task, unsigned) {
        for (const Set& s : sets_) {
            if (s.reserved == 0) continue;
            const auto n = Eigen::Index(s.cols.size());
            const Eigen::Map<const Eigen::MatrixXd> product(products_.data() + s.product_offset, n, n);
            const Eigen::Index shape = std::lower_bound(s.cols.begin(), s.cols.end(), K) - s.cols.begin();
            if (task == 0) {
                Eigen::MatrixXd& S = H.shape_block();
                for (Eigen::Index c = 0; c < shape; ++c)
                    for (Eigen::Index r = 0; r <= c; ++r) S(s.cols[std::size_t(r)], s.cols[std::size_t(c)]) += product(r, c);
                continue;
            }
            if (shape == n || (s.cols[std::size_t(shape)] - K) / B != task - 1) continue;
            Eigen::MatrixXd& band = H.band(uint32_t(task - 1));
            Eigen::MatrixXd& own = H.frame_block(uint32_t(task - 1));
            for (Eigen::Index c = shape; c < n; ++c) {
                const uint32_t lc = (s.cols[std::size_t(c)] - K) % B;
                for (Eigen::Index r = 0; r < shape; ++r) band(s.cols[std::size_t(r)], lc) += product(r, c);
                for (Eigen::Index r = shape; r <= c; ++r) own((s.cols[std::size_t(r)] - K) % B, lc) += product(r, c);
            }
        }
    });
}

void NormalEquations::add_to_upper(Eigen::MatrixXd& H, ThreadPool& pool) {
    multiply(pool);
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
            const auto n = Eigen::Index(s.cols.size());
            const Eigen::Map<const Eigen::MatrixXd> product(products_.data() + s.product_offset, n, n);
            // cols is sorted, so the upper triangle of the block lands in H's upper triangle.
            const auto first = std::lower_bound(s.cols.begin(), s.cols.end(), lo) - s.cols.begin();
            for (auto c = first; c < Eigen::Index(s.cols.size()) && s.cols[std::size_t(c)] < hi; ++c) {
                double* column = H.col(s.cols[std::size_t(c)]).data();
                for (Eigen::Index r = 0; r <= c; ++r) column[s.cols[std::size_t(r)]] += product(r, c);
            }
        }
    });
}

}  // namespace ssc::fitting
