#include "attributes.hpp"

#include "skeleton_fit.hpp"

#include "common/error.hpp"
#include "common/thread_pool.hpp"
#include "measure/measurements.hpp"
#include "semantics/made_to_measure.hpp"
#include "synthesis/body.hpp"
#include "synthesis/model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>

namespace ssc::training {
namespace {

struct Column {
    std::string name, unit, description;
    bool slider;
};

// The measurements the runtime takes, as attribute columns.
std::vector<Column> measured_columns() {
    std::vector<Column> out;
    const auto& defs = measure::definitions();
    for (const auto& d : defs) {
        const std::string name = d.name;
        if (name == "volume") continue;  // mass is volume times a constant: one of the two
        const char* unit = d.unit == measure::Unit::Metre ? "m" : d.unit == measure::Unit::SquareMetre ? "m2" : "kg";
        out.push_back({name, unit, d.definition, name == "stature" || name == "mass"});
    }
    return out;
}

unsigned workers() { return std::max(1u, std::min(8u, std::thread::hardware_concurrency())); }

}  // namespace

std::vector<KnownAttribute> population_attributes(const std::vector<BodyParams>& people) {
    std::vector<KnownAttribute> out = {
        {"sex", "", "Sex: 0 female, 1 male (values between blend the two).", true, {}},
        {"age", "years", "Age in years.", true, {}},
        {"muscle", "", "Muscularity: the MakeHuman muscle slider, 0 (little muscle tone) to 1 (very muscular).", true, {}},
        {"proportions", "", "Body proportions: the MakeHuman proportions slider, 0 uncommon to 1 idealised.", true, {}},
    };
    for (const BodyParams& b : people) {
        out[0].values.push_back(b.male ? 1 : 0);
        out[1].values.push_back(b.age_years);
        out[2].values.push_back(b.macro.muscle);
        out[3].values.push_back(b.macro.proportions);
    }
    return out;
}

format::AttributeModel learn_attribute_model(const format::ModelData& data, const SampleMatrix& X, const Pca& p, uint32_t fit,
                                             const std::vector<KnownAttribute>& known) {
    const Model model(data, nullptr);
    const measure::Measurer measurer(model);
    const uint32_t K = model.component_count();
    std::vector<Column> cols = measured_columns();
    const std::size_t E = cols.size(), A = E + known.size();
    for (const KnownAttribute& k : known) {
        SSC_REQUIRE_ARG_S(k.values.size() >= fit, "attribute " << k.name << ": " << k.values.size() << " values for " << fit << " bodies");
        cols.push_back({k.name, k.unit, k.description, k.slider});
    }
    // Coefficients in standard deviations: projections on the principal directions.
    Eigen::MatrixXd coeff = (X.topRows(fit).cast<double>() * p.basis.cast<double>());
    for (uint32_t k = 0; k < K; ++k) coeff.col(k) /= p.stddev(k);

    Eigen::MatrixXd values(fit, Eigen::Index(A));
    ThreadPool pool(workers());
    std::vector<std::unique_ptr<Body>> bodies(pool.size());
    for (auto& b : bodies) b = std::make_unique<Body>(model, nullptr);
    std::mutex error_mutex;
    std::string error;
    pool.parallel_for(fit, [&](std::size_t i, unsigned w) {
        try {
            std::vector<float> c(K);
            for (uint32_t k = 0; k < K; ++k) c[k] = float(coeff(Eigen::Index(i), k));
            bodies[w]->set_shape(c.data(), K);
            const std::vector<double> m = measurer.measure(*bodies[w]);
            Eigen::Index col = 0;
            for (std::size_t d = 0; d < m.size(); ++d)
                if (std::string(measure::definitions()[d].name) != "volume") values(Eigen::Index(i), col++) = m[d];
            for (std::size_t a = 0; a < known.size(); ++a) values(Eigen::Index(i), Eigen::Index(E + a)) = known[a].values[i];
        } catch (const std::exception& e) {
            const std::lock_guard<std::mutex> lock(error_mutex);
            error = e.what();  // the last one is enough to report
        }
    });
    if (!error.empty()) fail(SSC_ERROR_INTERNAL, "measuring the training bodies: " + error);

    const Eigen::RowVectorXd mean = values.colwise().mean();
    const Eigen::MatrixXd dev = values.rowwise() - mean;
    const Eigen::MatrixXd cov = dev.transpose() * dev / double(fit - 1);
    const Eigen::MatrixXd cross = dev.transpose() * coeff / double(fit - 1);  // coefficients have zero mean

    format::AttributeModel out;
    for (std::size_t a = 0; a < A; ++a) {
        std::vector<double> sorted(values.col(Eigen::Index(a)).data(), values.col(Eigen::Index(a)).data() + fit);
        std::sort(sorted.begin(), sorted.end());
        format::Attribute at;
        at.name = cols[a].name, at.unit = cols[a].unit, at.description = cols[a].description, at.slider = cols[a].slider;
        at.mean = float(mean(Eigen::Index(a)));
        at.minimum = float(sorted[std::size_t(0.005 * (fit - 1))]);
        at.maximum = float(sorted[std::size_t(0.995 * (fit - 1))]);
        out.attributes.push_back(at);
    }
    out.covariance.resize(A * A);
    out.shape_covariance.resize(A * K);
    for (std::size_t a = 0; a < A; ++a) {
        for (std::size_t b = 0; b < A; ++b)  // symmetric exactly, as the validator requires
            out.covariance[a * A + b] = float(a <= b ? cov(Eigen::Index(a), Eigen::Index(b)) : cov(Eigen::Index(b), Eigen::Index(a)));
        for (uint32_t k = 0; k < K; ++k) out.shape_covariance[a * K + k] = float(cross(Eigen::Index(a), k));
    }
    return out;
}

MadeToMeasureAccuracy evaluate_made_to_measure(const format::ModelData& data, const SampleMatrix& X, uint32_t first, uint32_t count,
                                               const std::vector<BodyParams>& people) {
    const Model model(data, nullptr);
    const measure::Measurer measurer(model);
    const semantics::AttributeModel attributes(data);
    MadeToMeasureAccuracy out;
    const std::vector<int> requested = {measure::find_measurement("stature"), measure::find_measurement("chest_girth"),
                                        measure::find_measurement("waist_girth"), measure::find_measurement("hip_girth")};
    for (int m : requested) out.measurements.push_back(measure::definitions()[std::size_t(m)].name);
    const std::size_t R = requested.size();
    out.mean_error.assign(R, 0), out.worst_error.assign(R, 0), out.start_mean_error.assign(R, 0);
    std::vector<std::vector<double>> errors(count, std::vector<double>(2 * R));
    std::vector<int> converged(count, 0);
    std::vector<double> seconds(count, 0);
    ThreadPool pool(workers());
    std::mutex error_mutex;
    std::string error;
    pool.parallel_for(count, [&](std::size_t i, unsigned) {
        try {
            const uint32_t b = first + uint32_t(i);
            const std::vector<float> xyz(X.row(b).data(), X.row(b).data() + X.cols());
            const auto& sk = data.skeleton;
            const std::vector<float> joints = apply_regressor(sk.regressor_offsets.data(), sk.regressor_vertices.data(),
                                                              sk.regressor_weights.data(), data.joint_count(), xyz.data());
            const std::vector<double> truth = measurer.measure(xyz.data(), joints.data());
            std::vector<semantics::MeasureTarget> targets;
            for (int m : requested) targets.push_back({m, truth[std::size_t(m)]});
            semantics::MadeToMeasureOptions o;
            o.known = {{attributes.find("sex"), people[b].male ? 1.0 : 0.0}, {attributes.find("age"), people[b].age_years}};
            const auto t0 = std::chrono::steady_clock::now();
            const auto r = semantics::make_to_measure(model, measurer, attributes, targets, o);
            seconds[i] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            converged[i] = r.converged;
            for (std::size_t k = 0; k < R; ++k) {
                errors[i][k] = std::abs(r.achieved[std::size_t(requested[k])] - truth[std::size_t(requested[k])]);
                errors[i][R + k] = std::abs(r.start[std::size_t(requested[k])] - truth[std::size_t(requested[k])]);
            }
        } catch (const std::exception& e) {
            const std::lock_guard<std::mutex> lock(error_mutex);
            error = e.what();
        }
    });
    if (!error.empty()) fail(SSC_ERROR_INTERNAL, "made-to-measure evaluation: " + error);
    for (uint32_t i = 0; i < count; ++i) {
        for (std::size_t k = 0; k < R; ++k) {
            out.mean_error[k] += errors[i][k] / count;
            out.worst_error[k] = std::max(out.worst_error[k], errors[i][k]);
            out.start_mean_error[k] += errors[i][R + k] / count;
        }
        out.converged += uint32_t(converged[i]);
        out.mean_seconds += seconds[i] / count;
    }
    out.bodies = count;
    return out;
}

}  // namespace ssc::training
