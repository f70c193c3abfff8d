// Basis quantization with a bounded error.
//
// Error measure: with every coefficient at +-3 standard deviations (any signs), a vertex moves by
// E(v) = || sum_k s_k * 3 * e_k(v) || where e_k(v) is the quantization error of component k at v.
// We bound the worst sign choice from above by min(sqrt(sum_axis (sum_k |3 e_k,axis|)^2),
// sum_k ||3 e_k||) and report the largest bound over the vertices: a guarantee, not an estimate.
//
// Step choice: the bound grows with the sum of the steps while the coded size grows with the sum of
// their logarithms, so one uniform step for all components is optimal. A component whose range
// would overflow 16 bits gets a coarser step of its own; the uniform step is then searched so the
// bound meets the tolerance.
#include "sscape_format/model_io.hpp"

#include "common/error.hpp"

#include <algorithm>
#include <cmath>

namespace ssc::format {
namespace {

QuantizedBasis quantize_with(const float* basis, uint32_t n, uint32_t K, double base_step) {
    QuantizedBasis qb;
    qb.components = K;
    qb.step.resize(K);
    qb.q.resize(static_cast<std::size_t>(K) * 3 * n);
    const std::size_t rows = 3 * static_cast<std::size_t>(n);
    for (uint32_t k = 0; k < K; ++k) {
        const float* b = basis + k * rows;
        double range = 0;
        for (std::size_t i = 0; i < rows; ++i) range = std::max(range, std::abs(double(b[i])));
        const double step = std::max(base_step, range / 32767.0);
        qb.step[k] = static_cast<float>(step);
        const double inv = 1.0 / double(qb.step[k]);
        for (std::size_t i = 0; i < rows; ++i) {
            const double v = std::nearbyint(double(b[i]) * inv);
            qb.q[k * rows + i] = static_cast<int16_t>(std::clamp(v, -32767.0, 32767.0));
        }
    }
    return qb;
}

}  // namespace

double quantization_error_bound(const float* basis, const QuantizedBasis& qb, uint32_t n) {
    const std::size_t rows = 3 * static_cast<std::size_t>(n);
    double worst = 0;
    for (uint32_t v = 0; v < n; ++v) {
        double axis_sum[3] = {0, 0, 0}, norm_sum = 0;
        for (uint32_t k = 0; k < qb.components; ++k) {
            double e2 = 0;
            for (int a = 0; a < 3; ++a) {
                const std::size_t i = k * rows + a * n + v;
                const double e = 3.0 * (double(basis[i]) - double(qb.step[k]) * qb.q[i]);
                axis_sum[a] += std::abs(e);
                e2 += e * e;
            }
            norm_sum += std::sqrt(e2);
        }
        const double by_axis =
            std::sqrt(axis_sum[0] * axis_sum[0] + axis_sum[1] * axis_sum[1] + axis_sum[2] * axis_sum[2]);
        worst = std::max(worst, std::min(by_axis, norm_sum));
    }
    return worst;
}

QuantizedBasis quantize_basis(const float* basis, uint32_t n, uint32_t K, double tolerance, QuantizeReport* report) {
    SSC_REQUIRE_ARG(tolerance > 0 && std::isfinite(tolerance), "quantization tolerance must be positive");
    for (std::size_t i = 0; i < static_cast<std::size_t>(K) * 3 * n; ++i)
        SSC_REQUIRE_ARG(std::isfinite(basis[i]), "basis value " + std::to_string(i) + " is not finite");
    // Bisection on log(step): the bound is monotone in the step up to rounding noise.
    double lo = std::log(1e-12), hi = std::log(1.0);
    QuantizedBasis best = quantize_with(basis, n, K, std::exp(lo));
    double best_err = quantization_error_bound(basis, best, n), best_step = std::exp(lo);
    for (int it = 0; it < 40; ++it) {
        const double mid = 0.5 * (lo + hi);
        QuantizedBasis qb = quantize_with(basis, n, K, std::exp(mid));
        const double err = quantization_error_bound(basis, qb, n);
        if (err <= tolerance) {
            lo = mid;
            best = std::move(qb);
            best_err = err;
            best_step = std::exp(mid);
        } else {
            hi = mid;
        }
    }
    if (best_err > tolerance)
        fail(SSC_ERROR_INVALID_ARGUMENT, "the basis cannot be quantized to 16 bits within the tolerance");
    if (report) *report = {best_err, best_step};
    return best;
}

}  // namespace ssc::format
