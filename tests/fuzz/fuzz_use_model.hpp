// What the model fuzz targets do with a model that loaded: everything a runtime user does first.
// Failures with a status are fine (SSC_ERROR_INTERNAL is a bug: it traps); crashes, sanitizer
// reports and hangs are what the fuzzer finds.
#pragma once

#include <sscape/sscape.h>

#include <vector>

namespace fuzz {

inline void expect(ssc_status s) {
    if (s == SSC_ERROR_INTERNAL) __builtin_trap();
}

inline void use_model(ssc_model* model) {
    ssc_body* body = nullptr;
    expect(ssc_body_create(model, nullptr, &body));
    if (!body) return;
    const uint32_t V = ssc_model_vertex_count(model), J = ssc_model_joint_count(model), K = ssc_model_shape_count(model);
    std::vector<float> shape(K, 1.f), quats(4ull * J, 0.f), out(3ull * V);
    for (uint32_t j = 0; j < J; ++j) {
        quats[4 * j] = 0.3f;  // a rotation of every joint about x
        quats[4 * j + 3] = 0.95f;
    }
    expect(ssc_body_set_shape(body, shape.data(), K));
    expect(ssc_body_set_pose(body, quats.data(), J, nullptr));
    expect(ssc_body_get_vertices(body, out.data(), V, 0));
    expect(ssc_body_get_normals(body, out.data(), V, 0));
    std::vector<float> landmarks(3ull * ssc_model_landmark_count(model) + 3);
    expect(ssc_body_get_landmarks(body, landmarks.data(), ssc_model_landmark_count(model), 0));
    std::vector<float> measurements(ssc_measurement_count());
    expect(ssc_body_measure(body, measurements.data(), uint32_t(measurements.size())));
    if (ssc_model_slider_count(model) > 0) expect(ssc_body_set_slider(body, 0, 0.f));
    for (uint32_t s = 0; s < ssc_model_segment_count(model); ++s) {
        ssc_segment_info info{};
        info.struct_size = sizeof info;
        expect(ssc_model_get_segment_info(model, s, &info));
        std::vector<float> c(info.shape_count, -1.5f);
        expect(ssc_body_set_segment_shape(body, s, c.data(), info.shape_count));
    }
    if (ssc_model_segment_count(model) > 0) expect(ssc_body_get_vertices(body, out.data(), V, 0));
    ssc_body_destroy(body);
}

}  // namespace fuzz
