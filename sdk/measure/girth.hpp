// Girths: the perimeter of a body's cross-section in a plane, taken like a tape measure (the
// convex hull of the section, so the tape spans concavities such as the gap between the breasts
// or the buttocks).
//
// Sections are cut from edge lists (each mesh edge once) built once per body part, so cutting is
// one pass over that part's edges; horizontal_sections cuts many levels in the same single pass,
// which the searched levels (hip, calf, underbust) need.
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

// The unique edges (2 vertex indices each) of the triangles whose three vertices are all allowed
// (allowed[v] != 0; empty = all triangles).
std::vector<uint32_t> mesh_edges(const uint32_t* triangles, std::size_t triangle_count, const std::vector<uint8_t>& allowed);

// A mesh (packed xyz vertices) cut by a plane: one point per crossing edge, only points within
// max_radius of plane.point (so a neck section leaves out the shoulders).
std::vector<Eigen::Vector3d> plane_section(const float* xyz, const std::vector<uint32_t>& edges, const Plane& plane,
                                           double max_radius = 1e30);

// Horizontal sections at heights top, top - step, ..., count levels (metres): result[i] is the
// section at top - i * step. Equal to plane_section per level, in one pass over the edges.
std::vector<std::vector<Eigen::Vector3d>> horizontal_sections(const float* xyz, const std::vector<uint32_t>& edges,
                                                              double top, double step, int count);

// Tape-measure length around section points: the perimeter of their convex hull within the plane,
// metres (0 for fewer than 3 distinct points). `hull`, when given, receives the hull's corners in
// order (the path the tape takes).
double tape_girth(const std::vector<Eigen::Vector3d>& section, const Plane& plane,
                  std::vector<Eigen::Vector3d>* hull = nullptr);

// The horizontal plane at a height (y, metres): surveys take most girths in one.
inline Plane horizontal_plane(double height) { return Plane{Eigen::Vector3d(0, height, 0), Eigen::Vector3d::UnitY()}; }

}  // namespace ssc::measure
