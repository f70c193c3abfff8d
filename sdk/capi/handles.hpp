// The objects behind the opaque C handles. Contexts and models are reference counted: a model
// holds its context, a body holds its model, so callers may release handles in any order.
#pragma once

#include "common/error.hpp"
#include "common/alloc.hpp"
#include "common/thread_pool.hpp"
#include "fitting/fitter.hpp"
#include "registration/registrar.hpp"
#include "runtime/runtime_model.hpp"
#include "synthesis/body.hpp"
#include "synthesis/model.hpp"

#include <atomic>
#include <cstdarg>
#include <memory>
#include <string>
#include <vector>

struct ssc_context {
    std::atomic<uint32_t> refs{1};
    ssc::Allocator allocator;
    ssc_log_fn log = nullptr;
    void* log_user = nullptr;
    ssc_log_level log_level = SSC_LOG_WARNING;
    uint64_t max_model_bytes = 0;
    ssc::ThreadPool pool;

    explicit ssc_context(unsigned workers) : pool(workers) {}
    void message(ssc_log_level level, const std::string& text) const {
        if (log && level >= log_level) log(log_user, level, text.c_str());
    }
};

// The shim's view of a model: the C++ RuntimeModel (runtime/runtime_model.hpp) holds the state;
// the references name its parts for the C API's functions.
struct ssc_model {
    std::atomic<uint32_t> refs{1};
    ssc_context* context;  // holds one reference
    ssc::RuntimeModel runtime;
    const ssc::Model& model = runtime.model();
    const ssc::semantics::AttributeModel& attributes = runtime.attributes();  // sliders, made-to-measure regression
    const std::vector<ssc::anatomy::JointLimit>& limits = runtime.anatomy()->limits;  // per joint
    std::string digest;  // of the file's bytes it was loaded from (ssc::content_digest): what results record

    ssc_model(ssc_context* ctx, ssc::format::ModelData data) : context(ctx), runtime(std::move(data), &ctx->allocator) {}

    const ssc::measure::Measurer& measurer() const { return runtime.measurer(); }
};

struct ssc_body {
    ssc_model* model;  // holds one reference
    ssc::Body body;

    explicit ssc_body(ssc_model* m) : model(m), body(m->model, &m->context->allocator) {}
};

struct ssc_fitter {
    ssc_model* model;  // holds one reference
    ssc::fitting::Fitter fitter;
    ssc_frame_fn frame_callback = nullptr;  // ssc_fitter_set_frame_callback
    void* frame_user = nullptr;

    ssc_fitter(ssc_model* m, const ssc::fitting::FitOptions& o) : model(m), fitter(m->model, o, m->runtime.anatomy()) {}
};

struct ssc_registration {
    ssc_model* model;  // holds one reference
    ssc::registration::Registrar registrar;

    ssc_registration(ssc_model* m, const ssc::registration::RegistrationOptions& o)
        : model(m), registrar(m->model, o, m->runtime.anatomy()) {}
};

namespace ssc::capi {

inline Allocator allocator_of(const ssc_fitter* f) { return f->model->context->allocator; }
inline Allocator allocator_of(const ssc_registration* r) { return r->model->context->allocator; }
inline Allocator allocator_of(const ssc_context* c) { return c->allocator; }
inline Allocator allocator_of(const ssc_model* m) { return m->context->allocator; }
inline Allocator allocator_of(const ssc_body* b) { return b->model->context->allocator; }

// Objects live in memory from their context's allocator (the context itself: from its own).
template <class T, class... Args>
T* make(const Allocator& a, Args&&... args) {
    void* p = a.allocate(sizeof(T), alignof(T) < 64 ? 64 : alignof(T));
    try {
        return new (p) T(std::forward<Args>(args)...);
    } catch (...) {
        a.deallocate(p);
        throw;
    }
}

// Points (3 floats each at stride bytes, 0 = packed), optional normals at the same stride and optional
// packed confidences, copied into a cloud; the stride is checked here, the values by whoever takes
// the cloud (fitting/observations.hpp).
fitting::PointCloud copy_cloud(const float* points, const float* normals, const float* confidence, uint32_t count, size_t stride);

// A pose as set through the C API, checked (joint count, finite, non-zero quaternions, finite
// translation) and converted to unit quaternions, 4 per joint; NULL rotations = identity.
std::vector<float> checked_pose(const ssc_body* body, ssc_rotation_format format, const float* rotations, uint32_t joint_count,
                                const float* translation);

template <class T>
void unmake(T* p) {
    const Allocator a = allocator_of(p);
    p->~T();
    a.deallocate(p);
}


void context_retain(ssc_context* ctx);
void context_release(ssc_context* ctx);

}  // namespace ssc::capi
