#include "cpp_access.hpp"

#include "handles.hpp"

namespace ssc {

const Model& model_of(const ssc_model* model) { return model->model; }
Body& body_of(ssc_body* body) { return body->body; }
const measure::Measurer& measurer_of(const ssc_model* model) { return model->measurer(); }

}  // namespace ssc
