#include "closest_on_mesh.hpp"

#include <algorithm>
#include <cmath>

namespace ssc::training {

using Eigen::Vector3d;

std::array<double, 3> closest_barycentric(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c) {
    // Ericson, Real-Time Collision Detection, 5.1.5.
    const Vector3d ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
    const Vector3d bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return {1 - v, v, 0};
    }
    const Vector3d cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        return {1 - w, 0, w};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {0, 1 - w, w};
    }
    const double denom = 1 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    return {1 - v - w, v, w};
}

namespace {

Vector3d at(const std::vector<float>& xyz, uint32_t v) { return Vector3d(xyz[3 * std::size_t(v)], xyz[3 * std::size_t(v) + 1], xyz[3 * std::size_t(v) + 2]); }

}  // namespace

MeshClosest::MeshClosest(const std::vector<float>& xyz, const std::vector<uint32_t>& triangles) : xyz_(xyz), triangles_(triangles) {
    const std::size_t count = triangles.size() / 3;
    centroids_.reserve(count);
    for (std::size_t f = 0; f < count; ++f) {
        const Vector3d a = at(xyz, triangles[3 * f]), b = at(xyz, triangles[3 * f + 1]), c = at(xyz, triangles[3 * f + 2]);
        const Vector3d centroid = (a + b + c) / 3;
        centroids_.push_back(centroid);
        reach_ = std::max({reach_, (a - centroid).norm(), (b - centroid).norm(), (c - centroid).norm()});
    }
    if (count) index_ = std::make_unique<fitting::PointIndex>(centroids_);
}

std::pair<uint32_t, std::array<double, 3>> MeshClosest::operator()(const Vector3d& p) const {
    std::pair<uint32_t, std::array<double, 3>> out{0, {1, 0, 0}};
    if (!index_) return out;
    const auto distance2 = [&](uint32_t f, std::array<double, 3>& w) {
        const Vector3d a = at(xyz_, triangles_[3 * std::size_t(f)]), b = at(xyz_, triangles_[3 * std::size_t(f) + 1]),
                       c = at(xyz_, triangles_[3 * std::size_t(f) + 2]);
        w = closest_barycentric(p, a, b, c);
        return (w[0] * a + w[1] * b + w[2] * c - p).squaredNorm();
    };
    // The nearest centroid's triangle bounds the distance; a triangle with a point within that
    // distance has its centroid within it plus the reach (a small margin for rounding). Centroids
    // come nearest first, more each round, until one lies beyond that radius.
    const uint32_t first = index_->nearest(p, nullptr);
    double best = distance2(first, out.second);
    out.first = first;
    const double radius = (std::sqrt(best) + reach_) * (1 + 1e-9) + 1e-12;
    std::vector<uint32_t> found;
    std::vector<double> found2;
    for (std::size_t k = 16;; k *= 2) {  // (each round checks its centroids from the nearest: ties may come in another order)
        k = std::min(k, centroids_.size());
        found.resize(k), found2.resize(k);
        const std::size_t n = index_->nearest_k(p, k, found.data(), found2.data());
        for (std::size_t i = 0; i < n && found2[i] <= radius * radius; ++i) {
            std::array<double, 3> w;
            const double d = distance2(found[i], w);
            if (d < best || (d == best && found[i] < out.first)) best = d, out = {found[i], w};
        }
        if (n < k || n == centroids_.size() || found2[n - 1] > radius * radius) break;
    }
    return out;
}

}  // namespace ssc::training
