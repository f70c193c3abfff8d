#include "runtime/runtime_model.hpp"

#include "common/error.hpp"

namespace ssc {

RuntimeModel::RuntimeModel(format::ModelData data, const Allocator* alloc)
    : model_(std::move(data), alloc), anatomy_(std::make_shared<const anatomy::ModelAnatomy>(model_)), attributes_(model_.data()) {}

const measure::Measurer& RuntimeModel::measurer() const {
    std::lock_guard<std::mutex> lock(measurer_mutex_);
    if (!measurer_ && measurer_error_.empty()) {
        try {
            measurer_ = std::make_unique<measure::Measurer>(model_);
        } catch (const Error& e) {
            if (e.status() == SSC_ERROR_OUT_OF_MEMORY) throw;
            measurer_status_ = e.status();
            measurer_error_ = e.what();
        }
    }
    if (!measurer_) fail(measurer_status_, measurer_error_);
    return *measurer_;
}

}  // namespace ssc
