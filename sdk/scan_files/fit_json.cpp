#include "scan_files/fit_json.hpp"

#include "common/error.hpp"
#include "fitting/observations.hpp"
#include "synthesis/shape_range.hpp"

#include <algorithm>
#include <cmath>

namespace ssc::scan_files {

nlohmann::ordered_json fit_to_json(const Model& model, const fitting::FitState& f) {
    std::vector<double> rotations;
    for (const auto& q : f.pose) rotations.insert(rotations.end(), {q.x(), q.y(), q.z(), q.w()});
    const std::size_t K = std::min<std::size_t>(f.shape.size(), model.component_count());
    const std::vector<double> whole(f.shape.begin(), f.shape.begin() + std::ptrdiff_t(K)), segments(f.shape.begin() + std::ptrdiff_t(K), f.shape.end());
    nlohmann::ordered_json j = {{"shape", whole}, {"rotations_xyzw", rotations}, {"translation_m", {f.translation.x(), f.translation.y(), f.translation.z()}},
                                {"scale", f.scale}, {"frame", "the scan's, turned so that scan_up is +Y, in metres"}};
    if (!segments.empty()) j["segment_shape"] = segments;
    return j;
}

fitting::FitState fit_from_json(const nlohmann::ordered_json& fit, const Model& model) {
    const uint32_t J = model.joint_count();
    std::vector<double> shape = fit.at("shape");
    const std::vector<double> rotations = fit.at("rotations_xyzw"), translation = fit.at("translation_m");
    const std::vector<double> segments = fit.contains("segment_shape") ? fit.at("segment_shape").get<std::vector<double>>() : std::vector<double>();
    SSC_REQUIRE_ARG(rotations.size() == 4 * std::size_t(J) && translation.size() == 3 && shape.size() <= model.component_count() &&
                        segments.size() <= model.segment_coefficient_count() && (segments.empty() || shape.size() == model.component_count()),
                    "the fit's sizes do not match the model");
    shape.insert(shape.end(), segments.begin(), segments.end());
    fitting::FitState f;
    f.shape = shape;
    for (uint32_t k = 0; k < J; ++k) f.pose.emplace_back(rotations[4 * k + 3], rotations[4 * k], rotations[4 * k + 1], rotations[4 * k + 2]);
    f.translation = Eigen::Vector3d(translation[0], translation[1], translation[2]);
    f.scale = fit.at("scale").get<double>();
    // What a fit can hold: shapes within the library's range, a body's scale, unit rotations, a
    // position within the fitter's coordinates. Anything else is a corrupt or edited file.
    SSC_REQUIRE_ARG_S(std::isfinite(f.scale) && f.scale >= 0.1 && f.scale <= 10, "the fit's scale " << f.scale << " is outside [0.1, 10]");
    SSC_REQUIRE_ARG(f.translation.allFinite() && f.translation.cwiseAbs().maxCoeff() <= fitting::kMaxCoordinate,
                    "the fit's translation is not finite or beyond 1e6 m");
    for (std::size_t k = 0; k < shape.size(); ++k)
        SSC_REQUIRE_ARG_S(std::isfinite(shape[k]) && std::abs(shape[k]) <= kShapeLimit,
                          "the fit's shape coefficient " << k << " is " << shape[k] << "; shape coefficients lie within +-" << kShapeLimit);
    for (const auto& q : f.pose)
        SSC_REQUIRE_ARG(q.coeffs().allFinite() && std::abs(q.norm() - 1) <= 1e-3, "the fit's rotations_xyzw holds a value that is not a unit quaternion");
    return f;
}

}  // namespace ssc::scan_files
