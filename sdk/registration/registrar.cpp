#include "registration/registrar.hpp"

#include "common/error.hpp"

#include <cmath>

namespace ssc::registration {

namespace {

const RegistrationOptions& checked(const RegistrationOptions& o) {
    SSC_REQUIRE_ARG(std::isfinite(o.stiffness) && o.stiffness > 0 && o.stiffness <= 1e6, "registration: stiffness must be in (0, 1e6]");
    SSC_REQUIRE_ARG(std::isfinite(o.landmarks) && o.landmarks >= 0 && o.landmarks <= 1e6, "registration: landmark weight must be in [0, 1e6]");
    SSC_REQUIRE_ARG(std::isfinite(o.gamma) && o.gamma > 0 && o.gamma <= 1e3, "registration: gamma must be in (0, 1e3]");
    SSC_REQUIRE_ARG(o.max_iterations >= 1 && o.max_iterations <= 100, "registration: max_iterations must be 1 to 100");
    SSC_REQUIRE_ARG(o.initialisation == Initialisation::Model || o.initialisation == Initialisation::Rigid ||
                        o.initialisation == Initialisation::Rbf,
                    "registration: unknown initialisation");
    SSC_REQUIRE_ARG(std::isfinite(o.rbf_scale) && o.rbf_scale > 0 && o.rbf_scale <= 10, "registration: rbf_scale must be in (0, 10] metres");
    SSC_REQUIRE_ARG(o.rbf_kernel == RbfKernel::ThinPlate || o.rbf_kernel == RbfKernel::Multiquadric || o.rbf_kernel == RbfKernel::Gaussian,
                    "registration: unknown rbf kernel");
    SSC_REQUIRE_ARG(o.schedule == Schedule::Relaxed || o.schedule == Schedule::Constant, "registration: unknown schedule");
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
    result_ = register_scan(linear_, scan_, options_, progress, pool);
    return *result_;
}

const Registration& Registrar::result() const {
    SSC_REQUIRE_ARG(result_.has_value(), "registration: not run yet (or its input changed since)");
    return *result_;
}

}  // namespace ssc::registration
