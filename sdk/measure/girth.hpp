// Girths: the perimeter of a body's cross-section in a plane, taken like a tape measure (the
// convex hull of the section, so the tape spans concavities such as the gap between the breasts
// or the buttocks).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace ssc::measure {

struct Plane {
    Eigen::Vector3d point;   // metres
    Eigen::Vector3d normal;  // unit
};

// The mesh (packed xyz vertices, 3 indices per triangle) cut by a plane: one point per crossing
// edge, from triangles whose three vertices are all allowed (allowed[v] != 0; empty = all), and
// only points within max_radius of plane.point (so a neck section leaves out the shoulders).
std::vector<Eigen::Vector3d> plane_section(const float* xyz, const uint32_t* triangles, std::size_t triangle_count,
                                           const std::vector<uint8_t>& allowed, const Plane& plane,
                                           double max_radius = 1e30);

// Tape-measure length around section points: the perimeter of their convex hull within the plane,
// metres (0 for fewer than 3 distinct points). `hull`, when given, receives the hull's corners in
// order (the path the tape takes).
double tape_girth(const std::vector<Eigen::Vector3d>& section, const Plane& plane,
                  std::vector<Eigen::Vector3d>* hull = nullptr);

// Horizontal tape girth at a height (y, metres): the common case of surveys.
double girth_at(const float* xyz, const uint32_t* triangles, std::size_t triangle_count, const std::vector<uint8_t>& allowed,
                double height);

}  // namespace ssc::measure
