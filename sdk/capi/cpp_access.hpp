// The one bridge from C API handles to the C++ objects behind them, for in-tree C++ clients that
// hold handles but need what the C API does not offer: the command line's pictures (the renderer
// and simulator take a Model), the measurement paths of a body. Declarations only: the handles'
// layout stays private to sdk/capi. Lifetimes are the handles'.
#pragma once

#include <sscape/sscape.h>

#include <cstddef>

namespace ssc {
class Model;
class Body;
namespace measure {
class Measurer;
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

}  // namespace ssc
