// A registration of one scan: its input (the scan, named landmarks), options and result. What the
// C API's ssc_registration wraps, as ssc_fitter wraps fitting::Fitter; the work is register_scan().
#pragma once

#include "registration/register_scan.hpp"

#include <memory>
#include <optional>

namespace ssc::registration {

class Registrar {
public:
    // Checks the options (ssc::Error, INVALID_ARGUMENT). The model must outlive the registrar;
    // anatomy: the model's, shared (null: derived here).
    Registrar(const Model& model, const RegistrationOptions& options, std::shared_ptr<const anatomy::ModelAnatomy> anatomy = nullptr);

    const Model& model() const { return linear_.model; }
    const RegistrationOptions& options() const { return options_; }

    // The scan: checked whole (check_scan, register_scan.hpp) before it replaces the one before.
    // Forgets the result.
    void set_scan(fitting::PointCloud cloud, std::vector<uint32_t> triangles = {});
    // Landmarks on the scan (model landmark indices); replace the ones before. Forgets the result.
    void set_landmarks(std::vector<fitting::LandmarkTarget> landmarks);

    // Registers the scan (register_scan); INVALID_ARGUMENT without a scan, CANCELLED.
    const Registration& run(const RegistrationProgress& progress = {}, ThreadPool* pool = nullptr);

    // Forgets the result (the scan stays).
    void forget_result() { result_.reset(); }

    // After a run (else INVALID_ARGUMENT).
    bool done() const { return result_.has_value(); }
    const Registration& result() const;

private:
    RegistrationOptions options_;
    fitting::LinearModel linear_;
    Scan scan_;
    bool has_scan_ = false;
    std::optional<Registration> result_;
};

}  // namespace ssc::registration
