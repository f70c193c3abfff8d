// A loaded model and what is derived from it once, shared read-only by every body, fitter and
// measurement of it: the anatomy (joint limits and roles), the attribute model (sliders, bodies
// made to measure) and the measurer (built on first use). What the C API's ssc_model wraps.
#pragma once

#include "anatomy/model_anatomy.hpp"
#include "common/alloc.hpp"
#include "measure/measurements.hpp"
#include "semantics/attribute_model.hpp"
#include "synthesis/model.hpp"

#include <memory>
#include <mutex>
#include <string>

namespace ssc {

class RuntimeModel {
public:
    // Takes the validated file contents; alloc must outlive the model. Throws ssc::Error where the
    // derived data refuse the file (a singular slider covariance).
    RuntimeModel(format::ModelData data, const Allocator* alloc);
    RuntimeModel(const RuntimeModel&) = delete;
    RuntimeModel& operator=(const RuntimeModel&) = delete;

    const Model& model() const { return model_; }
    const std::shared_ptr<const anatomy::ModelAnatomy>& anatomy() const { return anatomy_; }
    const semantics::AttributeModel& attributes() const { return attributes_; }

    // Built on first use: its edge lists cost milliseconds that loading should not pay. Thread-safe.
    // A model without the landmarks the definitions need fails (SSC_ERROR_NOT_FOUND) and that
    // failure is kept: later calls report it without building again. Running out of memory is not
    // kept, so a later call may succeed.
    const measure::Measurer& measurer() const;

private:
    Model model_;
    std::shared_ptr<const anatomy::ModelAnatomy> anatomy_;
    semantics::AttributeModel attributes_;
    // A mutex, not std::call_once: a once-callable that throws is retried, which some pthread_once
    // implementations and ThreadSanitizer handle badly.
    mutable std::mutex measurer_mutex_;
    mutable std::unique_ptr<measure::Measurer> measurer_;
    mutable ssc_status measurer_status_ = SSC_ERROR_INTERNAL;
    mutable std::string measurer_error_;
};

}  // namespace ssc
