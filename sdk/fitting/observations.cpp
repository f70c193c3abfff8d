#include "fitting/observations.hpp"

#include "common/error.hpp"
#include "sscape_format/model_data.hpp"

#include <cmath>

namespace ssc::fitting {

bool measured_point(const Vector3d& p) { return p.allFinite() && p.cwiseAbs().maxCoeff() <= kMaxCoordinate; }

void validate_landmark(const format::ModelData& model, const LandmarkTarget& l, const std::string& where) {
    SSC_REQUIRE_ARG_S(l.landmark < model.landmarks.size(),
                      where << ": landmark index " << l.landmark << " is out of range (the model has " << model.landmarks.size() << ")");
    SSC_REQUIRE_ARG_S(measured_point(l.position), where << ": landmark " << model.landmarks[l.landmark].name
                                                        << " is not finite or has a coordinate beyond " << kMaxCoordinate);
    SSC_REQUIRE_ARG_S(l.weight > 0 && std::isfinite(l.weight), where << ": landmark weights must be positive");
}

void validate_cloud(const PointCloud& c, const std::string& where) {
    SSC_REQUIRE_ARG_S(c.normals.empty() || c.normals.size() == c.points.size(),
                      where << ": " << c.normals.size() << " normals for " << c.points.size() << " points");
    SSC_REQUIRE_ARG_S(c.confidence.empty() || c.confidence.size() == c.points.size(),
                      where << ": " << c.confidence.size() << " confidences for " << c.points.size() << " points");
    for (std::size_t i = 0; i < c.points.size(); ++i) {
        SSC_REQUIRE_ARG_S(measured_point(c.points[i]), where << ": point " << i << " is not finite or has a coordinate beyond " << kMaxCoordinate);
        if (!c.normals.empty())
            SSC_REQUIRE_ARG_S(c.normals[i].allFinite() && (c.normals[i].squaredNorm() == 0 || std::abs(c.normals[i].norm() - 1) < 1e-3),
                              where << ": normal " << i << " is neither a unit vector nor zero (unknown)");
        if (!c.confidence.empty())
            SSC_REQUIRE_ARG_S(c.confidence[i] >= 0 && c.confidence[i] <= 1, where << ": confidence " << i << " is not in [0, 1]");
    }
}

void validate_frame(const format::ModelData& model, const Frame& frame, const std::string& where) {
    for (const auto& l : frame.landmarks) validate_landmark(model, l, where);
    std::size_t points = 0;
    for (const auto& c : frame.clouds) {
        validate_cloud(c, where);
        points += c.points.size();
    }
    SSC_REQUIRE_ARG_S(frame.landmarks.size() >= 3 || points >= 16, where << " has too little data (at least 3 landmarks or 16 points)");
}

}  // namespace ssc::fitting
