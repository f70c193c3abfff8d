// Body measurements (measure/measurements.hpp) through the C API.
#include "guard.hpp"
#include "handles.hpp"
#include "measure/measurements.hpp"

#include <string>

using namespace ssc;
using namespace ssc::capi;

namespace {

ssc_unit to_c(measure::Unit u) {
    switch (u) {
        case measure::Unit::Metre: return SSC_UNIT_METRE;
        case measure::Unit::SquareMetre: return SSC_UNIT_SQUARE_METRE;
        case measure::Unit::CubicMetre: return SSC_UNIT_CUBIC_METRE;
        case measure::Unit::Kilogram: return SSC_UNIT_KILOGRAM;
    }
    return SSC_UNIT_METRE;
}

uint32_t find(const char* name) {
    need(name, "name");
    const int m = measure::find_measurement(name);
    if (m < 0) fail(SSC_ERROR_NOT_FOUND, std::string("no measurement named '") + name + "'");
    return uint32_t(m);
}

}  // namespace

extern "C" {

uint32_t ssc_measurement_count(void) { return uint32_t(measure::definitions().size()); }

ssc_status ssc_measurement_get_info(uint32_t measurement, const char** out_name, ssc_unit* out_unit, const char** out_definition) {
    return guarded(__func__, [&] {
        const auto& defs = measure::definitions();
        SSC_REQUIRE_ARG(measurement < defs.size(), "measurement " + std::to_string(measurement) + " is out of range (count " +
                                                       std::to_string(defs.size()) + ")");
        if (out_name) *out_name = defs[measurement].name;
        if (out_unit) *out_unit = to_c(defs[measurement].unit);
        if (out_definition) *out_definition = defs[measurement].definition;
    });
}

ssc_status ssc_measurement_find(const char* name, uint32_t* out_measurement) {
    return guarded(__func__, [&] {
        need(out_measurement, "out_measurement");
        *out_measurement = find(name);
    });
}

ssc_status ssc_body_measure(ssc_body* body, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(body, "body");
        check_output(out, capacity, measure::definitions().size(), 0, 4);
        const auto values = body->model->measurer().measure(body->body);
        for (std::size_t i = 0; i < values.size(); ++i) out[i] = float(values[i]);
    });
}

ssc_status ssc_body_measure_by_name(ssc_body* body, const char* name, float* out) {
    return guarded(__func__, [&] {
        need(body, "body");
        need(out, "out");
        const uint32_t m = find(name);
        *out = float(body->model->measurer().measure(body->body)[m]);
    });
}

}  // extern "C"
