// What a fit is given: landmarks and point clouds of a person, in frames (one pose each), and the
// one set of rules every entry point checks them by (the C API, fitting::Fitter, fit()).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace ssc::format {
struct ModelData;
}

namespace ssc::fitting {

using Eigen::Vector3d;

struct LandmarkTarget {
    uint32_t landmark = 0;  // model landmark index
    Vector3d position;      // metres
    double weight = 1;      // relative confidence, > 0
};

struct PointCloud {
    std::vector<Vector3d> points;      // metres
    std::vector<Vector3d> normals;     // empty, or one per point: unit, or zero where unknown (estimated)
    std::vector<double> confidence;    // empty or one weight in [0, 1] per point
};

// One observation of the person in one pose.
struct Frame {
    std::vector<LandmarkTarget> landmarks;
    std::vector<PointCloud> clouds;
};

// Measured coordinates beyond this magnitude (metres, or the data's unit when scale is fitted)
// are no measurement of a person: they would overflow extents and centroids.
constexpr double kMaxCoordinate = 1e6;

// Whether a measured point (landmark, cloud point) is finite and within kMaxCoordinate.
bool measured_point(const Vector3d& p);

// Throw ssc::Error(SSC_ERROR_INVALID_ARGUMENT), the message starting with `where`, for a landmark
// index beyond the model's, a position that is no measurement, or a weight that is not positive.
void validate_landmark(const format::ModelData& model, const LandmarkTarget& target, const std::string& where);

// The same for a cloud: every point a measurement, normals and confidences absent or one per
// point, normals unit or zero (unknown), confidences in [0, 1].
void validate_cloud(const PointCloud& cloud, const std::string& where);

// Points that cannot be a scan of a body, whatever their count: all at a few places (two clusters of
// identical points once fitted as converged, 6.5 SD of shape) or in one plane (a wall, a floor).
// Throws INVALID_ARGUMENT naming `where`. Linear in the points; stops counting places early.
void validate_spread(const std::vector<const std::vector<Vector3d>*>& clouds, const std::string& where);

// A frame's landmarks and clouds, and enough of them to fit: 3 landmarks or 16 points.
void validate_frame(const format::ModelData& model, const Frame& frame, const std::string& where);

}  // namespace ssc::fitting
