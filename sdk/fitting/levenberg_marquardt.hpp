// The Levenberg-Marquardt core of a fit: linearise, solve the damped step, apply it, keep it if the
// cost went down, else damp more. What is linearised (the energy, its correspondences) is the
// problem's; how long a stage runs is the stage's (stages.hpp).
#pragma once

#include "common/thread_pool.hpp"
#include "fitting/arrow_system.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace ssc::fitting {

// A stage also ends when Stage::stall iterations in a row fail to beat its best cost by this
// fraction: correspondences are found again every iteration, so the cost keeps moving by a little
// even at the solution.
constexpr double kPlateau = 2e-3;

// A least-squares problem as the core sees it.
class LeastSquaresProblem {
public:
    virtual ~LeastSquaresProblem() = default;
    // Prepares an iteration (correspondences found again) and returns the cost with the normal
    // equations of its linearisation.
    virtual double linearize(ArrowSystem& H, Eigen::VectorXd& g) = 0;
    // The columns the step solves for (sorted); the others stay.
    virtual std::vector<int> step_columns() const = 0;
    // Remembers the current state; restore() goes back to it.
    virtual void save() = 0;
    virtual void restore() = 0;
    // Applies a step and returns the cost there with the same correspondences.
    virtual double try_step(const Eigen::VectorXd& delta) = 0;
};

struct LmSettings {
    uint32_t iterations;  // at most
    double tolerance;     // converged when a step lowers the cost by less than this fraction
    uint32_t stall;       // iterations without a gain of kPlateau that end it
};

// Called with the iteration (counted over the whole fit) and the cost; false cancels.
using LmProgress = std::function<bool(uint32_t iteration, double cost)>;

// Runs at most settings.iterations iterations; `iteration` counts them (over the whole fit).
// Returns whether it converged (a step gained less than the tolerance, or the stage stalled);
// `cancelled` is set when progress returned false (the state is then the last accepted one).
// first_cost: set to the first iteration's cost when that is the fit's iteration 0.
bool levenberg_marquardt(LeastSquaresProblem& problem, const LmSettings& settings, const LmProgress* progress,
                         uint32_t& iteration, bool& cancelled, double* first_cost, ThreadPool& pool);

}  // namespace ssc::fitting
