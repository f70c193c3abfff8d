// Levels of detail: level 0 the full mesh, levels 1.. the model's (Model::level(level - 1)).
#include "guard.hpp"
#include "handles.hpp"

#include <cstring>

using namespace ssc;
using namespace ssc::capi;

namespace {

// Level `level` of the model (0 the full mesh), after checking the index.
Model::LevelMesh level_at(const Model& model, uint32_t level) {
    SSC_REQUIRE_ARG_S(level <= model.level_count(), "level " << level << " is out of range (count " << model.level_count() + 1 << ", 0 the full mesh)");
    return model.level_mesh(level);
}

// SSC_ERROR_NOT_FOUND for a level without UVs.
void need_uvs(const Model::LevelMesh& l, uint32_t level) {
    if (l.uv_count == 0) fail(SSC_ERROR_NOT_FOUND, "level " + std::to_string(level) + " has no UVs");
}

// Copies count items of per_item values to out, after checking its capacity (in items).
template <class T>
void copy_out(const T* values, uint32_t count, std::size_t per_item, T* out, uint32_t capacity) {
    check_output(out, capacity, count, 0, sizeof(T) * per_item);
    std::copy(values, values + std::size_t(count) * per_item, out);
}

}  // namespace

extern "C" {

uint32_t ssc_model_level_count(const ssc_model* model) { return model ? model->model.level_count() + 1 : 0; }

ssc_status ssc_model_get_level_info(const ssc_model* model, uint32_t level, ssc_level_info* out) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(out, "out");
        SSC_REQUIRE_ARG(out->struct_size >= sizeof(uint32_t) && out->struct_size <= sizeof(ssc_level_info),
                        "out->struct_size is " + std::to_string(out->struct_size) + "; expected sizeof(ssc_level_info)");
        const Model::LevelMesh l = level_at(model->model, level);
        ssc_level_info info{};
        info.struct_size = out->struct_size;
        info.name = l.name;
        info.vertex_count = l.vertex_count;
        info.triangle_count = l.triangle_count;
        info.uv_count = l.uv_count;
        std::memcpy(out, &info, out->struct_size);
    });
}

ssc_status ssc_model_get_level_triangles(const ssc_model* model, uint32_t level, uint32_t* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(model, "model");
        const Model::LevelMesh l = level_at(model->model, level);
        copy_out(l.triangles, l.triangle_count, 3, out, capacity);
    });
}

ssc_status ssc_model_get_level_uvs(const ssc_model* model, uint32_t level, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(model, "model");
        const Model::LevelMesh l = level_at(model->model, level);
        need_uvs(l, level);
        copy_out(l.uvs, l.uv_count, 2, out, capacity);
    });
}

ssc_status ssc_model_get_level_triangle_uvs(const ssc_model* model, uint32_t level, uint32_t* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(model, "model");
        const Model::LevelMesh l = level_at(model->model, level);
        need_uvs(l, level);
        copy_out(l.triangle_uvs, l.triangle_count, 3, out, capacity);
    });
}

ssc_status ssc_model_get_level_skin(const ssc_model* model, uint32_t level, uint16_t* joints, float* weights, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(model, "model");
        const Model::LevelMesh l = level_at(model->model, level);
        if (joints) check_output(joints, capacity, l.vertex_count, 0, 8);
        if (weights) check_output(weights, capacity, l.vertex_count, 0, 16);
        if (joints) std::copy(l.skin_joints, l.skin_joints + 4 * std::size_t(l.vertex_count), joints);
        if (weights) std::copy(l.skin_weights, l.skin_weights + 4 * std::size_t(l.vertex_count), weights);
    });
}

ssc_status ssc_model_get_level_sources(const ssc_model* model, uint32_t level, uint32_t* vertices, float* weights, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(model, "model");
        const uint32_t N = level_at(model->model, level).vertex_count;
        const format::DetailLevel* l = level ? &model->model.level(level - 1) : nullptr;
        if (vertices) check_output(vertices, capacity, N, 0, 16);
        if (weights) check_output(weights, capacity, N, 0, 16);
        for (uint32_t i = 0; i < N; ++i)
            for (uint32_t k = 0; k < 4; ++k) {
                if (vertices) vertices[4 * std::size_t(i) + k] = l ? l->sources[4 * std::size_t(i) + k] : i;
                if (weights) weights[4 * std::size_t(i) + k] = l ? l->source_weights[4 * std::size_t(i) + k] : (k == 0 ? 1.f : 0.f);
            }
    });
}

ssc_status ssc_model_get_level_landmarks(const ssc_model* model, uint32_t level, uint32_t* triangles, float* barycentric, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(model, "model");
        level_at(model->model, level);
        const format::DetailLevel* l = level ? &model->model.level(level - 1) : nullptr;
        const auto& d = model->model.data();
        const std::size_t L = d.landmarks.size();
        if (triangles) check_output(triangles, capacity, L, 0, 4);
        if (barycentric) check_output(barycentric, capacity, L, 0, 12);
        // A vertex landmark of the full mesh: the first triangle with that corner.
        auto corner_triangle = [&](uint32_t v, float* bc) {
            for (std::size_t i = 0; i < d.mesh.triangles.size(); ++i)
                if (d.mesh.triangles[i] == v) {
                    bc[0] = bc[1] = bc[2] = 0, bc[i % 3] = 1;
                    return uint32_t(i / 3);
                }
            fail(SSC_ERROR_INTERNAL, "landmark vertex " + std::to_string(v) + " is on no triangle");
        };
        for (std::size_t k = 0; k < L; ++k) {
            float bc[3];
            uint32_t t;
            if (l) {
                t = l->landmark_triangles[k];
                std::copy(&l->landmark_barycentric[3 * k], &l->landmark_barycentric[3 * k] + 3, bc);
            } else if (d.landmarks[k].vertex != format::kNone) {
                t = corner_triangle(d.landmarks[k].vertex, bc);
            } else {
                t = d.landmarks[k].triangle;
                std::copy(d.landmarks[k].barycentric, d.landmarks[k].barycentric + 3, bc);
            }
            if (triangles) triangles[k] = t;
            if (barycentric) std::copy(bc, bc + 3, barycentric + 3 * k);
        }
    });
}

ssc_status ssc_body_get_level_vertices(ssc_body* body, uint32_t level, float* out, uint32_t capacity, size_t stride) {
    if (level == 0) return ssc_body_get_vertices(body, out, capacity, stride);
    return guarded(__func__, [&] {
        need(body, "body");
        const uint32_t n = level_at(body->body.model(), level).vertex_count;
        stride = check_output(out, capacity, n, stride, 12);
        kernels::planar_to_xyz(body->body.level_posed(level - 1), n, out, stride);
    });
}

ssc_status ssc_body_get_level_normals(ssc_body* body, uint32_t level, float* out, uint32_t capacity, size_t stride) {
    if (level == 0) return ssc_body_get_normals(body, out, capacity, stride);
    return guarded(__func__, [&] {
        need(body, "body");
        const uint32_t n = level_at(body->body.model(), level).vertex_count;
        stride = check_output(out, capacity, n, stride, 12);
        copy_xyz(body->body.level_normals(level - 1), n, out, stride);
    });
}

ssc_status ssc_body_get_level_rest_vertices(ssc_body* body, uint32_t level, float* out, uint32_t capacity, size_t stride) {
    if (level == 0) return ssc_body_get_rest_vertices(body, out, capacity, stride);
    return guarded(__func__, [&] {
        need(body, "body");
        const uint32_t n = level_at(body->body.model(), level).vertex_count;
        stride = check_output(out, capacity, n, stride, 12);
        kernels::planar_to_xyz(body->body.level_rest(level - 1), n, out, stride);
    });
}

}  // extern "C"
