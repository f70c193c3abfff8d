#include "fitting/levenberg_marquardt.hpp"

#include <algorithm>
#include <limits>

namespace ssc::fitting {

namespace {
// Damping: the start of each stage, the factor a rejected step multiplies it by and an accepted
// one divides it by, its floor, and the steps tried per iteration.
constexpr double kInitialDamping = 1e-3, kDampingUp = 10, kDampingDown = 3, kMinDamping = 1e-7;
constexpr int kDampedAttempts = 8;
}  // namespace

bool levenberg_marquardt(LeastSquaresProblem& problem, const LmSettings& settings, const LmProgress* progress,
                         uint32_t& iteration, bool& cancelled, double* first_cost, ThreadPool& pool) {
    double mu = kInitialDamping;
    double best_cost = std::numeric_limits<double>::infinity();
    uint32_t stalled = 0;
    for (uint32_t it = 0; it < settings.iterations; ++it, ++iteration) {
        ArrowSystem H;
        Eigen::VectorXd g;
        const double cost = problem.linearize(H, g);
        if (first_cost && iteration == 0) *first_cost = cost;
        if (progress && *progress && !(*progress)(iteration, cost)) {
            cancelled = true;
            return false;
        }
        const std::vector<int> cols = problem.step_columns();
        // Damp until the cost (same correspondences) goes down.
        problem.save();
        bool improved = false;
        double new_cost = cost;
        for (int attempt = 0; attempt < kDampedAttempts && !improved; ++attempt) {
            const Eigen::VectorXd delta = H.damped_solve(g, cols, mu, pool);
            if (!delta.allFinite()) {
                mu *= kDampingUp;
                continue;
            }
            new_cost = problem.try_step(delta);
            if (new_cost < cost) {
                improved = true;
                mu = std::max(mu / kDampingDown, kMinDamping);
            } else {
                problem.restore();
                mu *= kDampingUp;
            }
        }
        if (!improved || cost - new_cost < settings.tolerance * std::max(cost, 1e-12)) {
            ++iteration;
            return true;
        }
        if (new_cost < best_cost * (1 - kPlateau)) {
            best_cost = new_cost;
            stalled = 0;
        } else if (++stalled >= settings.stall) {
            ++iteration;
            return true;
        }
    }
    return false;
}

}  // namespace ssc::fitting
