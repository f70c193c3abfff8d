#include "semantics/made_to_measure.hpp"

#include "common/error.hpp"
#include "synthesis/body.hpp"
#include "synthesis/shape_range.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <cstdio>
#include <string>

namespace ssc::semantics {
namespace {

// Residual scale per unit: the size of a difference that counts as one.
double unit_scale(measure::Unit u) {
    switch (u) {
        case measure::Unit::Metre: return 0.001;
        case measure::Unit::SquareMetre: return 0.001;
        case measure::Unit::CubicMetre: return 0.0001;
        case measure::Unit::Kilogram: return 0.1;
    }
    return 1;
}

// Targets a body can have: the population's widened range where the attribute model describes the
// measurement (AttributeModel::accepted_range), else a bound no person exceeds.
void check_target(const AttributeModel& attributes, const measure::Definition& def, double value) {
    const int a = attributes.find(def.name);
    if (a >= 0) return attributes.check_accepted(a, value);
    double limit = 1;
    const char* unit = "";
    switch (def.unit) {
        case measure::Unit::Metre: limit = measure::kMaxBodyExtent, unit = "m"; break;
        case measure::Unit::SquareMetre: limit = 10, unit = "m^2"; break;
        case measure::Unit::CubicMetre: limit = 1, unit = "m^3"; break;
        case measure::Unit::Kilogram: limit = 1000, unit = "kg"; break;
    }
    if (value > 0 && value <= limit) return;  // false for NaN
    char text[160];
    std::snprintf(text, sizeof text, "the requested %s %g %s is outside the accepted range: above 0, at most %g %s", def.name, value,
                  unit, limit, unit);
    fail(SSC_ERROR_INVALID_ARGUMENT, text);
}

// The box every shape stays in (shape_range.hpp).
Eigen::VectorXd in_range(const Eigen::VectorXd& c) { return c.unaryExpr(&within_shape_range); }

constexpr double kStartPull = 1e-2;  // weight of |c - start|^2 against 1 mm^2 of residual
constexpr double kStep = 0.05;       // forward-difference step, standard deviations

}  // namespace

MadeToMeasureResult make_to_measure(const Model& model, const measure::Measurer& measurer, const AttributeModel& attributes,
                                    const std::vector<MeasureTarget>& targets, const MadeToMeasureOptions& options) {
    const auto& defs = measure::definitions();
    SSC_REQUIRE_ARG(!targets.empty(), "no measurements requested");
    std::vector<bool> seen(defs.size(), false);
    for (const MeasureTarget& t : targets) {
        SSC_REQUIRE_ARG(t.measurement >= 0 && std::size_t(t.measurement) < defs.size(),
                        "measurement " + std::to_string(t.measurement) + " is out of range");
        SSC_REQUIRE_ARG(!seen[std::size_t(t.measurement)], std::string("measurement '") + defs[std::size_t(t.measurement)].name +
                                                               "' is requested twice");
        check_target(attributes, defs[std::size_t(t.measurement)], t.value);
        seen[std::size_t(t.measurement)] = true;
    }
    for (const auto& [a, v] : options.known)
        SSC_REQUIRE_ARG(a >= 0 && std::size_t(a) < attributes.attributes().size() && std::isfinite(v),
                        "a known attribute is out of range or not finite");

    // The regression's start from everything the attribute model knows of.
    std::vector<std::pair<int, double>> known = options.known;
    for (const MeasureTarget& t : targets) {
        const int a = attributes.find(defs[std::size_t(t.measurement)].name);
        if (a >= 0) known.emplace_back(a, t.value);
    }
    const uint32_t K = model.component_count();
    const Eigen::VectorXd start = in_range(attributes.conditional_shape(known));
    Eigen::VectorXd c = start;

    const Eigen::Index M = Eigen::Index(targets.size());
    Body body(model, nullptr);
    std::vector<float> cf(K);
    std::vector<double> all;
    // Iterations measure only what was requested; the start and the result are measured whole.
    std::vector<bool> requested(defs.size(), false);
    for (const MeasureTarget& t : targets) requested[std::size_t(t.measurement)] = true;
    auto evaluate = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r, bool whole = false) {
        for (uint32_t k = 0; k < K; ++k) cf[k] = float(x(k));
        body.set_shape(cf.data(), K);
        all = measurer.measure(body, nullptr, whole ? nullptr : &requested);
        r.resize(M);
        for (Eigen::Index i = 0; i < M; ++i) {
            const MeasureTarget& t = targets[std::size_t(i)];
            r(i) = (all[std::size_t(t.measurement)] - t.value) / unit_scale(defs[std::size_t(t.measurement)].unit);
        }
        return r.squaredNorm() + kStartPull * (x - start).squaredNorm();
    };
    auto within = [&](const Eigen::VectorXd& r) {
        return r.cwiseAbs().maxCoeff() <= options.tolerance / 0.001;  // residuals are in mm (or the unit's equivalent)
    };

    MadeToMeasureResult out;
    Eigen::VectorXd r, trial_r;
    double cost = evaluate(c, r, true);
    out.start = all;
    double mu = 1e-2;
    Eigen::MatrixXd Jm(M, K);
    for (out.iterations = 0; out.iterations < options.max_iterations && !within(r); ++out.iterations) {
        for (uint32_t k = 0; k < K; ++k) {
            Eigen::VectorXd x = c, rk;
            x(k) += kStep;
            evaluate(x, rk);
            Jm.col(k) = (rk - r) / kStep;
        }
        const Eigen::MatrixXd JtJ = Jm.transpose() * Jm;
        const Eigen::VectorXd g = Jm.transpose() * r + kStartPull * (c - start);
        bool improved = false;
        for (int attempt = 0; attempt < 6 && !improved; ++attempt) {
            Eigen::MatrixXd H = JtJ;
            H.diagonal().array() += kStartPull + mu;
            const Eigen::VectorXd x = in_range(c - H.ldlt().solve(g));
            const double trial = evaluate(x, trial_r);
            if (trial < cost) {
                c = x, r = trial_r, cost = trial;
                mu = std::max(1e-6, mu / 3);
                improved = true;
            } else {
                mu *= 8;
            }
        }
        if (!improved) break;
    }
    out.converged = within(r);
    evaluate(c, r, true);
    out.achieved = all;
    out.coefficients.assign(cf.size(), 0.f);
    for (uint32_t k = 0; k < K; ++k) out.coefficients[k] = float(c(k));
    return out;
}

}  // namespace ssc::semantics
