#include "cpp_access.hpp"

#include "handles.hpp"

namespace ssc {

const Model& model_of(const ssc_model* model) { return model->model; }
Body& body_of(ssc_body* body) { return body->body; }
const measure::Measurer& measurer_of(const ssc_model* model) { return model->measurer(); }

const ssc_model* model_of(const ssc_fitter* fitter) { return fitter->model; }
const ssc_model* model_of(const ssc_registration* registration) { return registration->model; }
const std::string& digest_of(const ssc_model* model) { return model->digest; }
ThreadPool& pool_of(const ssc_model* model) { return model->context->pool; }
void log_message(const ssc_model* model, ssc_log_level level, const std::string& text) { model->context->message(level, text); }
registration::Registrar& registrar_of(ssc_registration* registration) { return registration->registrar; }
const fitting::Fitter& fitter_of(const ssc_fitter* fitter) { return fitter->fitter; }

}  // namespace ssc
