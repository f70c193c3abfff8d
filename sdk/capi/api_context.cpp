// Version, status names, last error, contexts.
#include "guard.hpp"
#include "handles.hpp"

#include <thread>

using namespace ssc;
using namespace ssc::capi;

namespace ssc::capi {

namespace {
thread_local std::string t_last_error;
}

void set_last_error(const std::string& message) { t_last_error = message; }

std::size_t check_output(const void* out, uint64_t capacity, uint64_t count, std::size_t stride, std::size_t elem_bytes) {
    SSC_REQUIRE_ARG(out != nullptr, "output buffer is NULL");
    // Packed (stride 0): elements back to back, whatever their size; a given stride: rows of floats.
    if (stride == 0) stride = elem_bytes;
    else
        SSC_REQUIRE_ARG(stride >= elem_bytes && stride % 4 == 0,
                        "stride " + std::to_string(stride) + " must be 0 or a multiple of 4 that is >= " + std::to_string(elem_bytes));
    if (capacity < count)
        fail(SSC_ERROR_BUFFER_TOO_SMALL,
             "capacity " + std::to_string(capacity) + " is less than the " + std::to_string(count) + " elements needed");
    return stride;
}

void context_retain(ssc_context* ctx) { ctx->refs.fetch_add(1, std::memory_order_relaxed); }

void context_release(ssc_context* ctx) {
    if (ctx->refs.fetch_sub(1, std::memory_order_acq_rel) == 1) unmake(ctx);
}

}  // namespace ssc::capi

extern "C" {

uint32_t ssc_version(void) { return SSC_VERSION_NUMBER; }

const char* ssc_status_name(ssc_status status) {
    switch (status) {
        case SSC_OK: return "SSC_OK";
        case SSC_ERROR_INVALID_ARGUMENT: return "SSC_ERROR_INVALID_ARGUMENT";
        case SSC_ERROR_OUT_OF_MEMORY: return "SSC_ERROR_OUT_OF_MEMORY";
        case SSC_ERROR_BUFFER_TOO_SMALL: return "SSC_ERROR_BUFFER_TOO_SMALL";
        case SSC_ERROR_IO: return "SSC_ERROR_IO";
        case SSC_ERROR_MODEL_CORRUPT: return "SSC_ERROR_MODEL_CORRUPT";
        case SSC_ERROR_UNSUPPORTED_VERSION: return "SSC_ERROR_UNSUPPORTED_VERSION";
        case SSC_ERROR_NOT_FOUND: return "SSC_ERROR_NOT_FOUND";
        case SSC_ERROR_CANCELLED: return "SSC_ERROR_CANCELLED";
        case SSC_ERROR_INTERNAL: return "SSC_ERROR_INTERNAL";
        default: return "SSC_UNKNOWN_STATUS";
    }
}

const char* ssc_last_error(void) { return t_last_error.c_str(); }

void ssc_context_def_init(ssc_context_def* def, size_t size) {
    if (!def || size < sizeof(uint32_t)) return;
    ssc_context_def d{};
    d.struct_size = static_cast<uint32_t>(size < sizeof d ? size : sizeof d);
    d.worker_count = 0;
    d.log_level = SSC_LOG_WARNING;
    std::memcpy(def, &d, d.struct_size);
}

ssc_status ssc_context_create(const ssc_context_def* def, ssc_context** out) {
    return guarded(__func__, [&] {
        need(out, "out");
        const ssc_context_def d = read_def(def, ssc_context_def_init, "def");
        SSC_REQUIRE_ARG((d.alloc == nullptr) == (d.free == nullptr), "alloc and free must be set together");
        const int32_t level = enum_value(d.log_level);
        SSC_REQUIRE_ARG(level >= SSC_LOG_DEBUG && level <= SSC_LOG_ERROR,
                        "def->log_level is " + std::to_string(level) + "; expected SSC_LOG_DEBUG (0) to SSC_LOG_ERROR (3)");
        unsigned workers = d.worker_count;
        if (workers == 0) workers = std::max(1u, std::thread::hardware_concurrency());
        SSC_REQUIRE_ARG(workers <= 1024, "worker_count is larger than 1024");
#if defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)
        workers = 1;  // WebAssembly without threads (the browser runtime): everything on the caller's thread
#endif
        Allocator a{d.alloc, d.free, d.alloc_user};
        ssc_context* ctx = make<ssc_context>(a, workers);
        ctx->allocator = a;
        ctx->log = d.log;
        ctx->log_user = d.log_user;
        ctx->log_level = d.log_level;
        ctx->max_model_bytes = d.max_model_bytes;
        *out = ctx;
    });
}

void ssc_context_destroy(ssc_context* ctx) {
    if (ctx) context_release(ctx);
}

}  // extern "C"
