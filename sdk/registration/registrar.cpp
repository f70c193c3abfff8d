#include "registration/registrar.hpp"

#include "common/error.hpp"

#include <cmath>

namespace ssc::registration {


namespace {

const RegistrationOptions& checked(const RegistrationOptions& o) {
    check_options(o);
    return o;
}

}  // namespace

Registrar::Registrar(const Model& model, const RegistrationOptions& options, std::shared_ptr<const anatomy::ModelAnatomy> anatomy)
    : options_(checked(options)), linear_(model, model.component_count(), std::move(anatomy), options_.segments, options_.segments_left_out) {}

void Registrar::set_scan(fitting::PointCloud cloud, std::vector<uint32_t> triangles) {
    check_scan(cloud, triangles);
    scan_.cloud = std::move(cloud);
    scan_.triangles = std::move(triangles);
    has_scan_ = true;
    result_.reset();
}

void Registrar::set_landmarks(std::vector<fitting::LandmarkTarget> landmarks) {
    for (std::size_t l = 0; l < landmarks.size(); ++l)
        fitting::validate_landmark(model().data(), landmarks[l], "registration: landmark " + std::to_string(l));
    std::vector<uint8_t> given(model().data().landmarks.size(), 0);  // one position per landmark
    for (const auto& l : landmarks) {
        SSC_REQUIRE_ARG_S(!given[l.landmark], "registration: landmark " << model().data().landmarks[l.landmark].name << " is given twice");
        given[l.landmark] = 1;
    }
    scan_.landmarks = std::move(landmarks);
    result_.reset();
}

const Registration& Registrar::run(const RegistrationProgress& progress, ThreadPool* pool) {
    SSC_REQUIRE_ARG(has_scan_, "registration: no scan (set one first)");
    result_.reset();
    result_ = register_checked_scan(linear_, scan_, options_, progress, pool);  // checked as it was set
    return *result_;
}

const Registration& Registrar::result() const {
    SSC_REQUIRE_ARG(result_.has_value(), "registration: not run yet (or its input changed since)");
    return *result_;
}

}  // namespace ssc::registration
