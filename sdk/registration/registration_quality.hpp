// How well a registration covers its scan, as the reference papers measure it: each scan point's
// distance to the registered surface, and the share of template vertices within 2, 5, 10 and 20 mm
// of a compatible scan point, overall and per body region (a low mean can hide a failed hand).
#pragma once

#include "common/thread_pool.hpp"
#include "fitting/nearest.hpp"
#include "sscape_format/model_data.hpp"

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace ssc::registration {

// The thresholds of the registration-to-scan shares, metres.
constexpr std::array<double, 4> kBelow = {0.002, 0.005, 0.010, 0.020};

struct DistanceSummary {
    double mean = 0, median = 0, p95 = 0;  // metres
    std::size_t count = 0;
    std::size_t beyond_20mm = 0;  // of them farther than 20 mm: scan the registration does not follow (or clutter)
};

struct RegionQuality {
    std::string region;                  // a vertex set's name
    DistanceSummary scan_to_registration;  // the scan points whose nearest registered vertex is in the region
    std::array<double, 4> below{};       // shares of the region's vertices within kBelow of the scan
    std::size_t vertices = 0;
};

struct RegistrationQuality {
    DistanceSummary scan_to_registration;
    std::array<double, 4> below{};  // shares of all template vertices
    std::vector<RegionQuality> regions;
    // Per template vertex: its distance to the scan as the shares count it, or -1 where no compatible
    // scan point lies within 5 cm.
    std::vector<double> vertex_distance;
};

// The body regions a report is broken down by: the model's vertex sets (head, torso, arms, ...),
// each vertex in the first set that holds it, -1 in none.
struct BodyRegions {
    std::vector<std::string> names;
    std::vector<int> of_vertex;  // index into names, or -1
};
BodyRegions body_regions(const format::ModelData& model);

// The registered mesh (vertices, triangles, unit vertex normals, each vertex's region: an index
// into region_names or -1), and the scan (points, unit or zero normals, a k-d tree over the points).
// A vertex counts as matched within d when its nearest scan point (closer than 5 cm, normals less
// than 60 degrees apart, up to sign when the scan's normals are not oriented) lies within d, along
// that point's normal where it has one (the distance to the scan's tangent plane there).
RegistrationQuality registration_quality(const std::vector<Eigen::Vector3d>& vertices, const std::vector<uint32_t>& triangles,
                                         const std::vector<Eigen::Vector3d>& vertex_normals, const std::vector<int>& region,
                                         const std::vector<std::string>& region_names, const std::vector<Eigen::Vector3d>& points,
                                         const std::vector<Eigen::Vector3d>& normals, bool oriented, const fitting::PointIndex& index,
                                         ThreadPool& pool);

// The distance from p to the triangle (a, b, c).
double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// Unit area-weighted vertex normals of a triangle mesh (zero for a vertex no triangle uses).
std::vector<Eigen::Vector3d> vertex_normals(const std::vector<Eigen::Vector3d>& vertices, const std::vector<uint32_t>& triangles);

}  // namespace ssc::registration
