#include "registration/registration_quality.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace ssc::registration {

namespace {

constexpr double kMatchDistance = 0.05;
const double kMatchCos = std::cos(60.0 * M_PI / 180.0);
// Registered vertices whose triangles are searched for each scan point's nearest surface point.
constexpr std::size_t kNearVertices = 6;

DistanceSummary summary(std::vector<double> d) {
    DistanceSummary s;
    s.count = d.size();
    if (d.empty()) return s;
    double sum = 0;
    for (double x : d) sum += x, s.beyond_20mm += x > 0.020;
    s.mean = sum / double(d.size());
    const auto at = [&](double q) {
        const std::size_t k = std::min(d.size() - 1, std::size_t(q * double(d.size())));
        std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(k), d.end());
        return d[k];
    };
    s.median = at(0.5);
    s.p95 = at(0.95);
    return s;
}

}  // namespace

BodyRegions body_regions(const format::ModelData& model) {
    BodyRegions r;
    r.of_vertex.assign(model.vertex_count(), -1);
    for (const auto& set : model.vertex_sets) {
        r.names.push_back(set.name);
        for (uint32_t v : set.vertices)
            if (r.of_vertex[v] < 0) r.of_vertex[v] = int(r.names.size() - 1);
    }
    return r;
}

double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    // The closest point by the triangle's Voronoi regions (Ericson, Real-Time Collision Detection, 5.1.5).
    const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return (p - a).norm();
    const Eigen::Vector3d bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return (p - b).norm();
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
    const Eigen::Vector3d cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return (p - c).norm();
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
    const double denom = 1.0 / (va + vb + vc);
    return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

std::vector<Eigen::Vector3d> vertex_normals(const std::vector<Eigen::Vector3d>& vertices, const std::vector<uint32_t>& triangles) {
    std::vector<Eigen::Vector3d> n(vertices.size(), Eigen::Vector3d::Zero());
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const uint32_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
        const Eigen::Vector3d f = (vertices[b] - vertices[a]).cross(vertices[c] - vertices[a]);  // twice the area
        n[a] += f, n[b] += f, n[c] += f;
    }
    for (auto& x : n)
        if (x.squaredNorm() > 0) x.normalize();
    return n;
}

RegistrationQuality registration_quality(const std::vector<Eigen::Vector3d>& vertices, const std::vector<uint32_t>& triangles,
                                         const std::vector<Eigen::Vector3d>& vnormals, const std::vector<int>& region,
                                         const std::vector<std::string>& region_names, const std::vector<Eigen::Vector3d>& points,
                                         const std::vector<Eigen::Vector3d>& normals, bool oriented, const fitting::PointIndex& index,
                                         ThreadPool& pool) {
    RegistrationQuality q;
    const std::size_t V = vertices.size(), R = region_names.size();
    // Registration to scan: each vertex's nearest scan point, compatible.
    std::vector<double> vertex_distance(V, std::numeric_limits<double>::infinity());
    constexpr std::size_t kChunks = 32;
    pool.parallel_for(kChunks, [&](std::size_t c, unsigned) {
        for (std::size_t v = c * V / kChunks; v < (c + 1) * V / kChunks; ++v) {
            double d2;
            const uint32_t i = index.nearest(vertices[v], &d2);
            const double dot = normals[i].squaredNorm() > 0 ? normals[i].dot(vnormals[v]) : 1.0;
            // To the nearest point's tangent plane where it has a normal: a scattered scan's nearest
            // point lies up to half its spacing aside even from a surface that matches exactly.
            if (d2 < kMatchDistance * kMatchDistance && (oriented ? dot : std::abs(dot)) >= kMatchCos)
                vertex_distance[v] = normals[i].squaredNorm() > 0 ? std::abs((vertices[v] - points[i]).dot(normals[i])) : std::sqrt(d2);
        }
    });
    std::vector<std::array<std::size_t, 4>> region_below(R + 1, std::array<std::size_t, 4>{});
    std::vector<std::size_t> region_count(R + 1, 0);
    for (std::size_t v = 0; v < V; ++v) {
        const std::size_t r = region[v] < 0 ? R : std::size_t(region[v]);
        ++region_count[r];
        for (std::size_t k = 0; k < kBelow.size(); ++k) region_below[r][k] += vertex_distance[v] < kBelow[k];
    }
    for (std::size_t k = 0; k < kBelow.size(); ++k) {
        std::size_t all = 0;
        for (std::size_t r = 0; r <= R; ++r) all += region_below[r][k];
        q.below[k] = V ? double(all) / double(V) : 0;
    }
    // Scan to registration: each point's distance to the triangles around its nearest vertices.
    std::vector<std::vector<uint32_t>> around(V);
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3)
        for (int k = 0; k < 3; ++k) around[triangles[t + std::size_t(k)]].push_back(uint32_t(t / 3));
    const fitting::PointIndex vertex_index(vertices);
    std::vector<double> point_distance(points.size());
    std::vector<int> point_region(points.size());
    pool.parallel_for(kChunks, [&](std::size_t c, unsigned) {
        uint32_t near[kNearVertices];
        double d2[kNearVertices];
        for (std::size_t i = c * points.size() / kChunks; i < (c + 1) * points.size() / kChunks; ++i) {
            const std::size_t found = vertex_index.nearest_k(points[i], kNearVertices, near, d2);
            double best = std::sqrt(d2[0]);
            for (std::size_t k = 0; k < found; ++k)
                for (uint32_t t : around[near[k]])
                    best = std::min(best, point_triangle_distance(points[i], vertices[triangles[3 * t]], vertices[triangles[3 * t + 1]],
                                                                  vertices[triangles[3 * t + 2]]));
            point_distance[i] = best;
            point_region[i] = region[near[0]];
        }
    });
    q.scan_to_registration = summary(point_distance);
    q.vertex_distance.resize(V);
    for (std::size_t v = 0; v < V; ++v) q.vertex_distance[v] = std::isfinite(vertex_distance[v]) ? vertex_distance[v] : -1.0;
    for (std::size_t r = 0; r < R; ++r) {
        RegionQuality rq;
        rq.region = region_names[r];
        rq.vertices = region_count[r];
        for (std::size_t k = 0; k < kBelow.size(); ++k) rq.below[k] = rq.vertices ? double(region_below[r][k]) / double(rq.vertices) : 0;
        std::vector<double> d;
        for (std::size_t i = 0; i < points.size(); ++i)
            if (point_region[i] == int(r)) d.push_back(point_distance[i]);
        rq.scan_to_registration = summary(std::move(d));
        q.regions.push_back(std::move(rq));
    }
    return q;
}

}  // namespace ssc::registration
