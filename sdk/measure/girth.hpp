// Girths: the perimeter of a body's horizontal cross-section, taken like a tape measure (the
// convex hull of the section, so the tape spans concavities). Part of the measurement stage.
#pragma once

#include <cstdint>
#include <vector>

namespace ssc::measure {

// The cross-section of the mesh (packed xyz vertices, 3 indices per triangle) with the plane
// y = height, restricted to triangles whose three vertices are all allowed (allowed[v] != 0; empty
// = all): the intersection points as (x, z) pairs.
std::vector<double> horizontal_section(const float* xyz, const uint32_t* triangles, std::size_t triangle_count,
                                       const std::vector<uint8_t>& allowed, double height);

// Perimeter of the convex hull of 2D points (x, z pairs), metres; 0 for fewer than 3 points.
double convex_perimeter(const std::vector<double>& xz);

// Tape girth at a height: convex_perimeter(horizontal_section(...)).
double girth_at(const float* xyz, const uint32_t* triangles, std::size_t triangle_count, const std::vector<uint8_t>& allowed,
                double height);

}  // namespace ssc::measure
