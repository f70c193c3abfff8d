// Bodies: shape and pose in, vertices, normals and transforms out.
#include "guard.hpp"
#include "handles.hpp"
#include "synthesis/random_shapes.hpp"
#include "synthesis/rotation.hpp"
#include "synthesis/shape_range.hpp"

#include <cmath>
#include <cstring>
#include <vector>

using namespace ssc;
using namespace ssc::capi;

namespace {

void check_finite(const float* v, std::size_t n, const char* what) {
    for (std::size_t i = 0; i < n; ++i)
        SSC_REQUIRE_ARG(std::isfinite(v[i]), std::string(what) + "[" + std::to_string(i) + "] is not finite");
}

void set_pose(ssc_body* body, ssc_rotation_format format, const float* rotations, uint32_t joint_count,
              const float* translation) {
    need(body, "body");
    body->body.set_pose(checked_pose(body, format, rotations, joint_count, translation).data(), translation);
}

void copy_matrices(const ssc_body* body, float* out, const float* src) {
    std::memcpy(out, src, sizeof(float) * 16 * body->body.model().joint_count());
}

}  // namespace

namespace ssc::capi {

std::vector<float> checked_pose(const ssc_body* body, ssc_rotation_format format, const float* rotations, uint32_t joint_count,
                                const float* translation) {
    const uint32_t J = body->body.model().joint_count();
    std::vector<float> quats(4ull * J, 0.f);
    if (rotations) {
        SSC_REQUIRE_ARG(joint_count == J, "joint_count is " + std::to_string(joint_count) + "; the model has " +
                                          std::to_string(J) + " joints");
        std::string error;
        SSC_REQUIRE_ARG(to_unit_quaternions(format, rotations, J, quats.data(), error), error);
    } else {
        SSC_REQUIRE_ARG(joint_count == 0 || joint_count == J, "joint_count must be 0 or the joint count when rotations is NULL");
        for (uint32_t j = 0; j < J; ++j) quats[4 * j + 3] = 1.f;
    }
    if (translation) check_finite(translation, 3, "translation");
    return quats;
}

}  // namespace ssc::capi

extern "C" {

void ssc_body_def_init(ssc_body_def* def, size_t size) {
    if (!def || size < sizeof(uint32_t)) return;
    ssc_body_def d{};
    d.struct_size = static_cast<uint32_t>(size < sizeof d ? size : sizeof d);
    std::memcpy(def, &d, d.struct_size);
}

ssc_status ssc_body_create(ssc_model* model, const ssc_body_def* def, ssc_body** out) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(out, "out");
        const ssc_body_def d = read_def(def, ssc_body_def_init, "def");
        SSC_REQUIRE_ARG(d.reserved == 0, "def->reserved must be 0");
        ssc_body* b = make<ssc_body>(allocator_of(model), model);
        ssc_model_retain(model);
        *out = b;
    });
}

void ssc_body_destroy(ssc_body* body) {
    if (!body) return;
    ssc_model* model = body->model;
    unmake(body);
    ssc_model_release(model);
}

ssc_status ssc_body_set_shape(ssc_body* body, const float* coefficients, uint32_t count) {
    return guarded(__func__, [&] {
        need(body, "body");
        const uint32_t K = body->body.model().component_count();
        SSC_REQUIRE_ARG(count <= K, "count is " + std::to_string(count) + "; the model has " + std::to_string(K) + " components");
        if (count) {
            need(coefficients, "coefficients");
            check_shape_coefficients(coefficients, count, "coefficients");
        }
        body->body.set_shape(coefficients, count);
    });
}

ssc_status ssc_body_get_shape(const ssc_body* body, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(body, "body");
        const uint32_t K = body->body.model().component_count();
        if (K == 0) return;
        check_output(out, capacity, K, 0, 4);
        std::memcpy(out, body->body.shape(), 4ull * K);
    });
}

ssc_status ssc_body_set_pose(ssc_body* body, const float* rotations, uint32_t joint_count, const float* translation) {
    return guarded(__func__, [&] { set_pose(body, SSC_ROTATION_QUATERNION, rotations, joint_count, translation); });
}

ssc_status ssc_model_sample_shapes(const ssc_model* model, uint32_t seed, uint32_t count, float truncation, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(model, "model");
        SSC_REQUIRE_ARG(truncation > 0 && truncation <= SSC_SHAPE_COEFFICIENT_LIMIT,
                        "truncation is " + std::to_string(truncation) + "; it must lie in (0, " +
                            std::to_string(SSC_SHAPE_COEFFICIENT_LIMIT) + "] standard deviations");
        const uint64_t needed = uint64_t(count) * model->model.component_count();
        SSC_REQUIRE_ARG(needed <= 0xFFFFFFFFu, "count x components exceeds 2^32 floats");
        if (needed == 0) return;  // no bodies, or a model without components (a template alone)
        check_output(out, capacity, uint32_t(needed), 0, 4);
        const std::vector<float> shapes = random_shapes(model->model, seed, count, truncation);
        std::memcpy(out, shapes.data(), 4 * shapes.size());
    });
}

ssc_status ssc_rotation_from_axis_angle(const float* axis_angle, float* out_xyzw) {
    return guarded(__func__, [&] {
        need(axis_angle, "axis_angle");
        need(out_xyzw, "out_xyzw");
        std::string error;
        float q[4];
        SSC_REQUIRE_ARG(to_unit_quaternions(SSC_ROTATION_AXIS_ANGLE, axis_angle, 1, q, error), error);
        std::memcpy(out_xyzw, q, sizeof q);
    });
}

ssc_status ssc_body_set_pose_axis_angle(ssc_body* body, const float* rotations, uint32_t joint_count,
                                        const float* translation) {
    return guarded(__func__, [&] { set_pose(body, SSC_ROTATION_AXIS_ANGLE, rotations, joint_count, translation); });
}

ssc_status ssc_body_get_vertices(ssc_body* body, float* out, uint32_t capacity, size_t stride) {
    return guarded(__func__, [&] {
        need(body, "body");
        const uint32_t V = body->body.model().vertex_count();
        stride = check_output(out, capacity, V, stride, 12);
        body->body.posed_xyz(out, stride);
    });
}

ssc_status ssc_body_get_normals(ssc_body* body, float* out, uint32_t capacity, size_t stride) {
    return guarded(__func__, [&] {
        need(body, "body");
        const uint32_t V = body->body.model().vertex_count();
        stride = check_output(out, capacity, V, stride, 12);
        copy_xyz(body->body.normals(), V, out, stride);
    });
}

ssc_status ssc_body_get_rest_vertices(ssc_body* body, float* out, uint32_t capacity, size_t stride) {
    return guarded(__func__, [&] {
        need(body, "body");
        const uint32_t V = body->body.model().vertex_count();
        stride = check_output(out, capacity, V, stride, 12);
        kernels::planar_to_xyz(body->body.rest_planar(), V, out, stride);
    });
}

ssc_status ssc_body_get_landmarks(ssc_body* body, float* out, uint32_t capacity, size_t stride) {
    return guarded(__func__, [&] {
        need(body, "body");
        const auto& d = body->body.model().data();
        stride = check_output(out, capacity, d.landmarks.size(), stride, 12);
        kernels::landmarks(d, body->body.posed(), out, stride);
    });
}

ssc_status ssc_body_get_joint_transforms(ssc_body* body, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(body, "body");
        check_output(out, capacity, body->body.model().joint_count(), 0, 64);
        copy_matrices(body, out, body->body.world());
    });
}

ssc_status ssc_body_get_inverse_bind_matrices(ssc_body* body, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(body, "body");
        check_output(out, capacity, body->body.model().joint_count(), 0, 64);
        copy_matrices(body, out, body->body.inverse_bind());
    });
}

ssc_status ssc_body_get_skinning_matrices(ssc_body* body, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(body, "body");
        const uint32_t J = body->body.model().joint_count();
        check_output(out, capacity, J, 0, 64);
        const kernels::SkinMatrix* s = body->body.skinning();
        for (uint32_t j = 0; j < J; ++j) std::memcpy(out + 16 * j, s[j].m, 64);
    });
}

}  // extern "C"
