// The one bridge from C API handles to the C++ objects behind them, for in-tree C++ clients that
// hold handles but need what the C API does not offer: the command line's pictures (the renderer
// and simulator take a Model), the measurement paths of a body, and the offline C API
// (sdk/capi_offline), which registers scan files with a registration's registrar. Declarations
// only: the handles' layout stays private to sdk/capi. Lifetimes are the handles'.
#pragma once

#include <sscape/sscape.h>

#include <cstddef>
#include <string>

namespace ssc {
class Model;
class Body;
class ThreadPool;
namespace measure {
class Measurer;
}
namespace fitting {
class Fitter;
}
namespace registration {
class Registrar;
}

const Model& model_of(const ssc_model* model);
Body& body_of(ssc_body* body);  // mutable: a body computes its stages lazily
// Built on first use and kept (thread-safe); throws ssc::Error where the model lacks the landmarks
// the measurements need.
const measure::Measurer& measurer_of(const ssc_model* model);

// The built-in model's file bytes as compiled in (model_format/models/sscape-default.sscape): what
// a tool that writes or digests "the built-in model" needs, without encoding it again (seconds).
struct FileBytes {
    const unsigned char* data;
    std::size_t size;
};
FileBytes default_model_file();

// For the offline C API: the model a fitter or a registration holds, the digest of the file a model
// was loaded from (what results record), its context's worker pool and log, a registration's
// registrar.
const ssc_model* model_of(const ssc_fitter* fitter);
const ssc_model* model_of(const ssc_registration* registration);
const std::string& digest_of(const ssc_model* model);
ThreadPool& pool_of(const ssc_model* model);
void log_message(const ssc_model* model, ssc_log_level level, const std::string& text);
registration::Registrar& registrar_of(ssc_registration* registration);
const fitting::Fitter& fitter_of(const ssc_fitter* fitter);

}  // namespace ssc
