// Segment shape spaces: per-segment coefficients on top of a body's whole-body shape.
#include "guard.hpp"
#include "handles.hpp"
#include "synthesis/shape_range.hpp"

#include <cstring>

using namespace ssc;
using namespace ssc::capi;

namespace {

const SegmentSpace& segment_at(const Model& model, uint32_t index) {
    SSC_REQUIRE_ARG(index < model.segments().size(), "segment " + std::to_string(index) + " is out of range (count " +
                                                         std::to_string(model.segments().size()) + ")");
    return model.segments()[index];
}

}  // namespace

uint32_t ssc_model_segment_count(const ssc_model* model) { return model ? uint32_t(model->model.segments().size()) : 0; }

ssc_status ssc_model_get_segment_info(const ssc_model* model, uint32_t index, ssc_segment_info* out) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(out, "out");
        SSC_REQUIRE_ARG(out->struct_size >= sizeof(uint32_t) && out->struct_size <= sizeof(ssc_segment_info),
                        "out->struct_size is " + std::to_string(out->struct_size) + "; expected sizeof(ssc_segment_info)");
        const SegmentSpace& s = segment_at(model->model, index);
        ssc_segment_info info{};
        info.struct_size = out->struct_size;
        info.name = s.name.c_str();
        info.shape_count = s.components;
        info.vertex_count = uint32_t(s.vertices.size());
        std::memcpy(out, &info, out->struct_size);
    });
}

ssc_status ssc_model_find_segment(const ssc_model* model, const char* name, uint32_t* out_index) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(name, "name");
        need(out_index, "out_index");
        const int64_t s = model->model.find_segment(name);
        if (s < 0) fail(SSC_ERROR_NOT_FOUND, std::string("the model has no segment named '") + name + "'");
        *out_index = uint32_t(s);
    });
}

ssc_status ssc_model_get_segment_vertices(const ssc_model* model, uint32_t index, uint32_t* vertices, float* weights,
                                          uint32_t capacity) {
    return guarded(__func__, [&] {
        need(model, "model");
        const SegmentSpace& s = segment_at(model->model, index);
        const auto n = uint32_t(s.vertices.size());
        if (vertices) check_output(vertices, capacity, n, 0, 4);
        if (weights) check_output(weights, capacity, n, 0, 4);
        if (vertices) std::memcpy(vertices, s.vertices.data(), 4ull * n);
        if (weights) std::memcpy(weights, s.weights.data(), 4ull * n);
    });
}

ssc_status ssc_body_set_segment_shape(ssc_body* body, uint32_t segment, const float* coefficients, uint32_t count) {
    return guarded(__func__, [&] {
        need(body, "body");
        const SegmentSpace& s = segment_at(body->body.model(), segment);
        SSC_REQUIRE_ARG(count <= s.components, "count is " + std::to_string(count) + "; segment '" + s.name + "' has " +
                                                   std::to_string(s.components) + " components");
        if (count) {
            need(coefficients, "coefficients");
            check_shape_coefficients(coefficients, count, "coefficients");
        }
        body->body.set_segment_shape(segment, coefficients, count);
    });
}

ssc_status ssc_body_get_segment_shape(const ssc_body* body, uint32_t segment, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(body, "body");
        const SegmentSpace& s = segment_at(body->body.model(), segment);
        check_output(out, capacity, s.components, 0, 4);
        std::memcpy(out, body->body.segment_shape(segment), 4ull * s.components);
    });
}
