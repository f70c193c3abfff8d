// Model loading and queries.
#include "common/files.hpp"
#include "guard.hpp"
#include "handles.hpp"
#include "sscape_format/model_io.hpp"

#include <algorithm>
#include <cstring>

using namespace ssc;
using namespace ssc::capi;

namespace {

// NULL ctx: a private context with default options (its threads start only if a batch runs).
ssc_context* context_for_load(ssc_context* ctx) {
    if (ctx) {
        context_retain(ctx);
        return ctx;
    }
    ssc_context* own = nullptr;
    const ssc_status s = ssc_context_create(nullptr, &own);
    if (s != SSC_OK) fail(s, ssc_last_error());
    return own;
}

template <class Read>
void load(ssc_context* ctx, ssc_model** out, Read&& read, const std::string& digest) {  // digest: read's, once it returns
    need(out, "out");
    ssc_context* c = context_for_load(ctx);
    try {
        format::ReadOptions options;
        options.max_model_bytes = c->max_model_bytes;
        options.allocator = &c->allocator;
        format::ModelData data = read(options);
        ssc_model* m = make<ssc_model>(c->allocator, c, std::move(data));
        m->digest = digest;
        c->message(SSC_LOG_INFO, "loaded model '" + m->model.data().metadata.name + "': " +
                                     std::to_string(m->model.vertex_count()) + " vertices, " +
                                     std::to_string(m->model.joint_count()) + " joints, " +
                                     std::to_string(m->model.component_count()) + " components");
        *out = m;
    } catch (const Error& e) {
        c->message(SSC_LOG_ERROR, e.what());
        context_release(c);
        throw;
    } catch (...) {
        context_release(c);
        throw;
    }
}

const format::ModelData& data(const ssc_model* m) { return m->model.data(); }

template <class T, class V>
void copy_out(const V& v, T* out, uint64_t capacity_elems, std::size_t per_elem) {
    check_output(out, capacity_elems, v.size() / per_elem, 0, sizeof(T) * per_elem);
    std::copy(v.begin(), v.end(), out);
}

}  // namespace

extern "C" {

ssc_status ssc_model_load_file(ssc_context* ctx, const char* path, ssc_model** out) {
    return guarded(__func__, [&] {
        need(path, "path");
        std::string digest;
        load(ctx, out, [&](const format::ReadOptions& o) { return format::read_model_file(path, o, &digest); }, digest);
    });
}

ssc_status ssc_model_load_memory(ssc_context* ctx, const void* bytes, size_t size, ssc_model** out) {
    return guarded(__func__, [&] {
        need(bytes, "data");
        load(ctx, out, [&](const format::ReadOptions& o) { return format::read_model(bytes, size, o); }, content_digest(bytes, size));
    });
}

void ssc_model_retain(ssc_model* model) {
    if (model) model->refs.fetch_add(1, std::memory_order_relaxed);
}

void ssc_model_release(ssc_model* model) {
    if (!model || model->refs.fetch_sub(1, std::memory_order_acq_rel) != 1) return;
    ssc_context* ctx = model->context;
    unmake(model);
    context_release(ctx);
}

uint32_t ssc_model_vertex_count(const ssc_model* m) { return m ? m->model.vertex_count() : 0; }
uint32_t ssc_model_triangle_count(const ssc_model* m) { return m ? m->model.triangle_count() : 0; }
uint32_t ssc_model_quad_count(const ssc_model* m) { return m ? uint32_t(data(m).mesh.quads.size() / 4) : 0; }
uint32_t ssc_model_uv_count(const ssc_model* m) { return m ? uint32_t(data(m).mesh.uvs.size() / 2) : 0; }
uint32_t ssc_model_joint_count(const ssc_model* m) { return m ? m->model.joint_count() : 0; }
uint32_t ssc_model_shape_count(const ssc_model* m) { return m ? m->model.component_count() : 0; }
uint32_t ssc_model_landmark_count(const ssc_model* m) { return m ? uint32_t(data(m).landmarks.size()) : 0; }
uint32_t ssc_model_vertex_set_count(const ssc_model* m) { return m ? uint32_t(data(m).vertex_sets.size()) : 0; }

ssc_status ssc_model_get_triangles(const ssc_model* m, uint32_t* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(m, "model");
        copy_out(data(m).mesh.triangles, out, capacity, 3);
    });
}

ssc_status ssc_model_get_quads(const ssc_model* m, uint32_t* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(m, "model");
        copy_out(data(m).mesh.quads, out, capacity, 4);
    });
}

ssc_status ssc_model_get_uvs(const ssc_model* m, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(m, "model");
        if (data(m).mesh.uvs.empty()) fail(SSC_ERROR_NOT_FOUND, "the model has no UVs");
        copy_out(data(m).mesh.uvs, out, capacity, 2);
    });
}

ssc_status ssc_model_get_triangle_uvs(const ssc_model* m, uint32_t* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(m, "model");
        if (data(m).mesh.uvs.empty()) fail(SSC_ERROR_NOT_FOUND, "the model has no UVs");
        copy_out(data(m).mesh.triangle_uvs, out, capacity, 3);
    });
}

ssc_status ssc_model_get_joint_parents(const ssc_model* m, int32_t* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(m, "model");
        copy_out(data(m).skeleton.parents, out, capacity, 1);
    });
}

ssc_status ssc_model_get_joint_name(const ssc_model* m, uint32_t index, const char** out) {
    return guarded(__func__, [&] {
        need(m, "model");
        need(out, "out");
        SSC_REQUIRE_ARG(index < m->model.joint_count(), "joint index " + std::to_string(index) + " is out of range");
        *out = data(m).skeleton.joint_names[index].c_str();
    });
}

ssc_status ssc_model_find_joint(const ssc_model* m, const char* name, uint32_t* out_index) {
    return guarded(__func__, [&] {
        need(m, "model");
        need(name, "name");
        need(out_index, "out_index");
        const int64_t i = m->model.find_joint(name);
        if (i < 0) fail(SSC_ERROR_NOT_FOUND, std::string("no joint named '") + name + "'");
        *out_index = static_cast<uint32_t>(i);
    });
}

ssc_status ssc_model_get_landmark_name(const ssc_model* m, uint32_t index, const char** out) {
    return guarded(__func__, [&] {
        need(m, "model");
        need(out, "out");
        SSC_REQUIRE_ARG(index < data(m).landmarks.size(), "landmark index " + std::to_string(index) + " is out of range");
        *out = data(m).landmarks[index].name.c_str();
    });
}

ssc_status ssc_model_find_landmark(const ssc_model* m, const char* name, uint32_t* out_index) {
    return guarded(__func__, [&] {
        need(m, "model");
        need(name, "name");
        need(out_index, "out_index");
        const int64_t i = m->model.find_landmark(name);
        if (i < 0) fail(SSC_ERROR_NOT_FOUND, std::string("no landmark named '") + name + "'");
        *out_index = static_cast<uint32_t>(i);
    });
}

ssc_status ssc_model_get_landmark_positions(const ssc_model* m, float* out, uint32_t capacity, size_t stride) {
    return guarded(__func__, [&] {
        need(m, "model");
        const std::size_t n = data(m).landmarks.size();
        stride = check_output(out, capacity, n, stride, 12);
        auto* base = reinterpret_cast<unsigned char*>(out);
        for (std::size_t l = 0; l < n; ++l) std::memcpy(base + l * stride, m->model.landmark_rest() + 3 * l, 12);
    });
}

ssc_status ssc_model_get_vertex_set(const ssc_model* m, uint32_t index, const char** out_name, uint32_t* out_size) {
    return guarded(__func__, [&] {
        need(m, "model");
        SSC_REQUIRE_ARG(index < data(m).vertex_sets.size(), "vertex set index " + std::to_string(index) + " is out of range");
        const auto& set = data(m).vertex_sets[index];
        if (out_name) *out_name = set.name.c_str();
        if (out_size) *out_size = static_cast<uint32_t>(set.vertices.size());
    });
}

ssc_status ssc_model_get_vertex_set_indices(const ssc_model* m, uint32_t index, uint32_t* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(m, "model");
        SSC_REQUIRE_ARG(index < data(m).vertex_sets.size(), "vertex set index " + std::to_string(index) + " is out of range");
        copy_out(data(m).vertex_sets[index].vertices, out, capacity, 1);
    });
}

ssc_status ssc_model_get_shape_stddevs(const ssc_model* m, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(m, "model");
        copy_out(data(m).shape.stddev, out, capacity, 1);
    });
}

ssc_status ssc_model_get_metadata(const ssc_model* m, ssc_metadata_key key, const char** out) {
    return guarded(__func__, [&] {
        need(m, "model");
        need(out, "out");
        const auto& md = data(m).metadata;
        const std::string* s = nullptr;
        switch (enum_value(key)) {
            case SSC_METADATA_NAME: s = &md.name; break;
            case SSC_METADATA_VERSION: s = &md.model_version; break;
            case SSC_METADATA_UNITS: s = &md.units; break;
            case SSC_METADATA_AXES: s = &md.axes; break;
            case SSC_METADATA_LICENSE: s = &md.license; break;
            case SSC_METADATA_PROVENANCE: s = &md.provenance; break;
            case SSC_METADATA_DESCRIPTION: s = &md.description; break;
            default: fail(SSC_ERROR_INVALID_ARGUMENT, "unknown metadata key " + std::to_string(enum_value(key)));
        }
        *out = s->c_str();
    });
}

ssc_status ssc_model_get_skin(const ssc_model* m, uint16_t* joints, float* weights, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(m, "model");
        const uint32_t V = m->model.vertex_count();
        if (joints) check_output(joints, capacity, V, 0, 8);
        if (weights) check_output(weights, capacity, V, 0, 16);
        if (joints) std::copy(data(m).skin.joints.begin(), data(m).skin.joints.end(), joints);
        if (weights) std::copy(data(m).skin.weights.begin(), data(m).skin.weights.end(), weights);
    });
}

}  // extern "C"
