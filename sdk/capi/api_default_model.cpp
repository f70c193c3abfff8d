// The default model compiled into the library (model_format/models/sscape-default.sscape,
// embedded by embed_default_model.S). It is loaded through the same verified path as any file.
#include "capi/cpp_access.hpp"
#include "capi/guard.hpp"

#include <sscape/sscape.h>

#include <cstddef>

#ifndef SSCAPE_NO_BUILTIN_MODEL
extern "C" {
extern const unsigned char ssc_internal_default_model[];
extern const unsigned char ssc_internal_default_model_end[];
}
#endif

namespace {
// The WebAssembly build leaves the model out of the module: a page fetches the file (cached by the
// browser, downloaded once for every page that uses it) and loads it from memory.
constexpr const char* kNoBuiltinModel =
    "this build has no built-in model (the WebAssembly runtime): fetch sscape-default.sscape and load it with ssc_model_load_memory";
}  // namespace

extern "C" {

ssc_status ssc_model_load_default(ssc_context* ctx, ssc_model** out) {
    const ssc::FileBytes file = ssc::default_model_file();
    if (!file.data) return ssc::capi::guarded(__func__, [] { ssc::fail(SSC_ERROR_NOT_FOUND, kNoBuiltinModel); });
    return ssc_model_load_memory(ctx, file.data, file.size, out);
}

ssc_status ssc_default_model_file(const void** out_data, size_t* out_size) {
    return ssc::capi::guarded(__func__, [&] {
        ssc::capi::need(out_data, "out_data");
        ssc::capi::need(out_size, "out_size");
        const ssc::FileBytes file = ssc::default_model_file();
        if (!file.data) ssc::fail(SSC_ERROR_NOT_FOUND, kNoBuiltinModel);
        *out_data = file.data;
        *out_size = file.size;
    });
}
}

ssc::FileBytes ssc::default_model_file() {
#ifdef SSCAPE_NO_BUILTIN_MODEL
    return {nullptr, 0};
#else
    return {ssc_internal_default_model, static_cast<std::size_t>(ssc_internal_default_model_end - ssc_internal_default_model)};
#endif
}
