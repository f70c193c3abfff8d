// Semantic sliders and bodies made to measure (semantics/) through the C API.
#include "guard.hpp"
#include "handles.hpp"
#include "semantics/made_to_measure.hpp"
#include "synthesis/shape_range.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

using namespace ssc;
using namespace ssc::capi;

namespace {

uint32_t slider_count(const ssc_model* model) { return uint32_t(model->attributes.sliders().size()); }

Eigen::VectorXd shape_of(const ssc_body* body) {
    const uint32_t K = body->body.model().component_count();
    Eigen::VectorXd c(K);
    for (uint32_t k = 0; k < K; ++k) c(k) = body->body.shape()[k];
    return c;
}

// Checked after narrowing to float: a finite double can still become an infinite float.
void set_shape(ssc_body* body, const Eigen::VectorXd& c) {
    std::vector<float> f(std::size_t(c.size()));
    for (Eigen::Index k = 0; k < c.size(); ++k) f[std::size_t(k)] = float(c(k));
    check_shape_coefficients(f.data(), f.size(), "the slider values give shape coefficient");
    body->body.set_shape(f.data(), uint32_t(f.size()));
}

}  // namespace

extern "C" {

uint32_t ssc_model_slider_count(const ssc_model* model) { return model ? slider_count(model) : 0; }

ssc_status ssc_model_get_slider_info(const ssc_model* model, uint32_t index, ssc_slider_info* out) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(out, "out");
        SSC_REQUIRE_ARG(out->struct_size >= sizeof(uint32_t) && out->struct_size <= sizeof(ssc_slider_info),
                        "out->struct_size is " + std::to_string(out->struct_size) + "; expected sizeof(ssc_slider_info)");
        SSC_REQUIRE_ARG(index < slider_count(model), "slider " + std::to_string(index) + " is out of range (count " +
                                                         std::to_string(slider_count(model)) + ")");
        const auto& a = model->attributes.attributes()[std::size_t(model->attributes.sliders()[index])];
        ssc_slider_info info{};
        info.struct_size = out->struct_size;
        info.name = a.name.c_str();
        info.unit = a.unit.c_str();
        info.description = a.description.c_str();
        info.mean = a.mean;
        info.minimum = a.minimum;
        info.maximum = a.maximum;
        std::memcpy(out, &info, out->struct_size);
    });
}

ssc_status ssc_model_find_slider(const ssc_model* model, const char* name, uint32_t* out_index) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(name, "name");
        need(out_index, "out_index");
        const auto& sliders = model->attributes.sliders();
        for (std::size_t i = 0; i < sliders.size(); ++i)
            if (model->attributes.attributes()[std::size_t(sliders[i])].name == name) {
                *out_index = uint32_t(i);
                return;
            }
        fail(SSC_ERROR_NOT_FOUND, std::string("the model has no slider named '") + name + "'");
    });
}

ssc_status ssc_body_get_sliders(const ssc_body* body, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(body, "body");
        const uint32_t S = slider_count(body->model);
        if (S == 0) return;
        check_output(out, capacity, S, 0, 4);
        const Eigen::VectorXd v = body->model->attributes.shape_to_sliders(shape_of(body));
        for (uint32_t i = 0; i < S; ++i) out[i] = float(v(i));
    });
}

ssc_status ssc_body_set_slider(ssc_body* body, uint32_t index, float value) {
    return guarded(__func__, [&] {
        need(body, "body");
        const uint32_t S = slider_count(body->model);
        SSC_REQUIRE_ARG(index < S, "slider " + std::to_string(index) + " is out of range (count " + std::to_string(S) + ")");
        const auto& am = body->model->attributes;
        am.check_accepted(am.sliders()[index], value);
        const Eigen::VectorXd c = shape_of(body);
        const double current = am.shape_to_sliders(c)(index);
        set_shape(body, c + am.slider_directions().col(index) * (double(value) - current));
    });
}

ssc_status ssc_body_set_sliders(ssc_body* body, const float* values, uint32_t count) {
    return guarded(__func__, [&] {
        need(body, "body");
        const uint32_t S = slider_count(body->model);
        SSC_REQUIRE_ARG(count == S, "count is " + std::to_string(count) + "; the model has " + std::to_string(S) + " sliders");
        if (S == 0) return;
        need(values, "values");
        Eigen::VectorXd v(S);
        for (uint32_t i = 0; i < S; ++i) {
            body->model->attributes.check_accepted(body->model->attributes.sliders()[i], values[i]);
            v(i) = values[i];
        }
        set_shape(body, body->model->attributes.sliders_to_shape(v));
    });
}

void ssc_made_to_measure_def_init(ssc_made_to_measure_def* def, size_t size) {
    if (!def || size < sizeof(uint32_t)) return;
    ssc_made_to_measure_def d{};
    d.struct_size = static_cast<uint32_t>(size < sizeof d ? size : sizeof d);
    d.sex = std::numeric_limits<float>::quiet_NaN();
    d.age = std::numeric_limits<float>::quiet_NaN();
    d.max_iterations = 15;
    d.tolerance = 0.0005f;
    std::memcpy(def, &d, d.struct_size);
}

ssc_status ssc_body_make_to_measure(ssc_body* body, const uint32_t* measurements, const float* values, uint32_t count,
                                    const ssc_made_to_measure_def* def, float* achieved, uint32_t achieved_capacity,
                                    uint32_t* out_converged) {
    return guarded(__func__, [&] {
        need(body, "body");
        need(measurements, "measurements");
        need(values, "values");
        SSC_REQUIRE_ARG(count >= 1, "count must be at least 1");
        const uint32_t M = uint32_t(measure::definitions().size());
        if (achieved) check_output(achieved, achieved_capacity, M, 0, 4);
        else SSC_REQUIRE_ARG(achieved_capacity == 0, "achieved_capacity must be 0 when achieved is NULL");
        const ssc_made_to_measure_def d = read_def(def, ssc_made_to_measure_def_init, "def");
        SSC_REQUIRE_ARG(d.max_iterations <= 1000, "def->max_iterations must be at most 1000");
        SSC_REQUIRE_ARG(std::isfinite(d.tolerance) && d.tolerance > 0, "def->tolerance must be finite and > 0");
        SSC_REQUIRE_ARG(std::isnan(d.sex) || (d.sex >= 0 && d.sex <= 1), "def->sex must be NaN (unknown) or in [0, 1]");
        SSC_REQUIRE_ARG(std::isnan(d.age) || (d.age > 0 && d.age < 150), "def->age must be NaN (unknown) or in (0, 150) years");

        std::vector<semantics::MeasureTarget> targets;
        for (uint32_t i = 0; i < count; ++i) {
            SSC_REQUIRE_ARG(measurements[i] < M, "measurements[" + std::to_string(i) + "] = " + std::to_string(measurements[i]) +
                                                     " is not an ssc_measurement value");
            targets.push_back({int(measurements[i]), double(values[i])});
        }
        const auto& am = body->model->attributes;
        semantics::MadeToMeasureOptions o;
        o.max_iterations = int(d.max_iterations);
        o.tolerance = d.tolerance;
        // Sex and age only steer the start, and only where the model's attributes know them.
        if (!std::isnan(d.sex) && am.find("sex") >= 0) o.known.emplace_back(am.find("sex"), d.sex);
        if (!std::isnan(d.age) && am.find("age") >= 0) o.known.emplace_back(am.find("age"), d.age);
        const auto r = semantics::make_to_measure(body->body.model(), body->model->measurer(), am, targets, o);
        body->body.set_shape(r.coefficients.data(), uint32_t(r.coefficients.size()));
        if (achieved)
            for (uint32_t m = 0; m < M; ++m) achieved[m] = float(r.achieved[m]);
        if (out_converged) *out_converged = r.converged ? 1 : 0;
    });
}

}  // extern "C"
