// Whether a scan's landmarks agree with the scan and with the model fit to it. A registration pulls
// its template's landmarks onto the given ones, so landmarks that are wrong (moved, in another
// frame, left and right exchanged) make a wrong registration that looks registered: once half of
// them moved 500 mm registered with exit 0. Judged here, before the deformation (docs/registration.md).
#pragma once

#include "fitting/kinematics.hpp"
#include "fitting/nearest.hpp"
#include "fitting/observations.hpp"
#include "sscape_format/model_data.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace ssc::registration {

// Metres from every scan point beyond which a landmark is not on the scan (a scan with holes, or one
// seen from the front, has its landmarks' surface within a body's depth).
constexpr double kLandmarkOffScan = 0.3;
// Metres between a given landmark and the fitted body's beyond which the landmark is off: on
// simulated scans (exact landmarks) the fitted body's lie 4 mm away at the median and 11 mm at
// most; hand-placed landmarks and a model's own definitions add a few centimetres.
constexpr double kLandmarkOff = 0.06;
// The share of landmarks off from which the landmarks as a whole disagree with the scan (and the
// registration is refused); fewer off are left out of the deformation.
constexpr double kLandmarksOffShare = 0.2;

// A template point (a landmark's barycentric place) on the given vertex positions.
Eigen::Vector3d point_on(const std::vector<Eigen::Vector3d>& vertices, const fitting::SurfacePoint& p);

// Throws ssc::Error (SSC_ERROR_INVALID_ARGUMENT) naming the landmarks farther than kLandmarkOffScan
// from every scan point.
void require_landmarks_on_scan(const format::ModelData& model, const std::vector<fitting::LandmarkTarget>& landmarks,
                               const fitting::PointIndex& scan);

struct LandmarkAgreement {
    std::vector<double> residual;  // per landmark: metres from the given position to the fitted body's landmark
    std::vector<uint8_t> off;      // per landmark: residual > kLandmarkOff
    std::size_t off_count = 0;
    bool swapped = false;  // the left and right landmarks fit the body once exchanged

    // Too many off: the landmarks disagree with the scan.
    bool disagrees() const { return off_count >= 3 && double(off_count) >= kLandmarksOffShare * double(residual.size()); }
    // "12 of 73 landmarks lie more than 6 cm from ... (Sellion 492 mm, ...)" and what that suggests.
    std::string describe(const format::ModelData& model, const std::vector<fitting::LandmarkTarget>& landmarks) const;
};

// The landmarks against a body fitted to the scan (its vertices, in the scan's frame).
LandmarkAgreement landmark_agreement(const format::ModelData& model, const std::vector<fitting::LandmarkTarget>& landmarks,
                                     const std::vector<Eigen::Vector3d>& fitted);

}  // namespace ssc::registration
