#include "fitting/surface_distance.hpp"

#include <algorithm>
#include <cmath>

namespace ssc::fitting {

using Eigen::Vector3d;

double point_triangle_distance(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c) {
    // The closest point by the triangle's Voronoi regions (Ericson, Real-Time Collision Detection, 5.1.5).
    const Vector3d ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return (p - a).norm();
    const Vector3d bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return (p - b).norm();
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
    const Vector3d cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return (p - c).norm();
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
    const double denom = 1.0 / (va + vb + vc);
    return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

SurfaceDistance::SurfaceDistance(const std::vector<Vector3d>& vertices, const uint32_t* triangles, std::size_t triangle_count)
    : vertices_(vertices), triangles_(triangles, triangles + 3 * triangle_count), ring_offsets_(vertices.size() + 1, 0),
      index_(vertices) {
    for (uint32_t v : triangles_) ++ring_offsets_[v + 1];
    for (std::size_t v = 0; v < vertices.size(); ++v) ring_offsets_[v + 1] += ring_offsets_[v];
    ring_.resize(triangles_.size());
    std::vector<uint32_t> next(ring_offsets_.begin(), ring_offsets_.end() - 1);
    for (std::size_t i = 0; i < triangles_.size(); ++i) ring_[next[triangles_[i]]++] = uint32_t(i / 3);
}

double SurfaceDistance::operator()(const Vector3d& q) const {
    double d2 = 0;
    const uint32_t k = index_.nearest(q, &d2);
    double d = std::sqrt(d2);
    for (uint32_t i = ring_offsets_[k]; i < ring_offsets_[k + 1]; ++i) {
        const uint32_t* t = &triangles_[3 * std::size_t(ring_[i])];
        d = std::min(d, point_triangle_distance(q, vertices_[t[0]], vertices_[t[1]], vertices_[t[2]]));
    }
    return d;
}

double share_beyond_surface(const SurfaceDistance& surface, const std::vector<Vector3d>& points, double distance) {
    if (points.empty()) return 0;
    std::size_t far = 0;
    for (const Vector3d& q : points) far += surface(q) > distance;
    return double(far) / double(points.size());
}

}  // namespace ssc::fitting
