#include "measure/girth.hpp"

#include <algorithm>
#include <cmath>

namespace ssc::measure {

using Eigen::Vector3d;

std::vector<uint32_t> mesh_edges(const uint32_t* tris, std::size_t count, const std::vector<uint8_t>& allowed) {
    std::vector<uint64_t> keys;
    keys.reserve(3 * count);
    for (std::size_t t = 0; t < count; ++t) {
        const uint32_t* c = tris + 3 * t;
        if (!allowed.empty() && !(allowed[c[0]] && allowed[c[1]] && allowed[c[2]])) continue;
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = c[e], b = c[(e + 1) % 3];
            keys.push_back(uint64_t(std::min(a, b)) << 32 | std::max(a, b));
        }
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    std::vector<uint32_t> edges;
    edges.reserve(2 * keys.size());
    for (uint64_t k : keys) {
        edges.push_back(uint32_t(k >> 32));
        edges.push_back(uint32_t(k));
    }
    return edges;
}

namespace {
Vector3d vertex(const float* xyz, uint32_t v) {
    return Vector3d(xyz[3 * std::size_t(v)], xyz[3 * std::size_t(v) + 1], xyz[3 * std::size_t(v) + 2]);
}
}  // namespace

std::vector<Vector3d> plane_section(const float* xyz, const std::vector<uint32_t>& edges, const Plane& plane, double max_radius) {
    std::vector<Vector3d> out;
    const double r2 = max_radius * max_radius;
    for (std::size_t e = 0; e + 1 < edges.size(); e += 2) {
        const Vector3d a = vertex(xyz, edges[e]), b = vertex(xyz, edges[e + 1]);
        const double da = (a - plane.point).dot(plane.normal), db = (b - plane.point).dot(plane.normal);
        if ((da < 0) == (db < 0)) continue;  // the edge does not cross the plane
        const Vector3d p = a + (da / (da - db)) * (b - a);
        if ((p - plane.point).squaredNorm() <= r2) out.push_back(p);
    }
    return out;
}

std::vector<std::vector<Vector3d>> horizontal_sections(const float* xyz, const std::vector<uint32_t>& edges, double top,
                                                       double step, int count) {
    std::vector<std::vector<Vector3d>> out(std::size_t(std::max(count, 0)));
    if (count <= 0 || !(step > 0)) return out;
    for (std::size_t e = 0; e + 1 < edges.size(); e += 2) {
        const Vector3d a = vertex(xyz, edges[e]), b = vertex(xyz, edges[e + 1]);
        // Levels i with the edge crossing y_i = top - i * step, by the same sign test as
        // plane_section: (a.y < y) != (b.y < y), i.e. y in (min, max].
        const double lo = std::min(a.y(), b.y()), hi = std::max(a.y(), b.y());
        if (!std::isfinite(lo) || !std::isfinite(hi)) continue;
        // Level bounds clamped in double before converting: far-away edges give quotients no int holds.
        const double from = std::ceil((top - hi) / step) - 1, to = std::floor((top - lo) / step) + 1;
        if (!(from <= count - 1) || !(to >= 0)) continue;  // wholly above or below the levels (or NaN)
        const int first = from <= 0 ? 0 : int(from);
        const int last = to >= count - 1 ? count - 1 : int(to);
        for (int i = first; i <= last; ++i) {
            const double y = top - i * step;
            const double da = a.y() - y, db = b.y() - y;
            if ((da < 0) == (db < 0)) continue;
            out[std::size_t(i)].push_back(a + (da / (da - db)) * (b - a));
        }
    }
    return out;
}

double tape_girth(const std::vector<Vector3d>& section, const Plane& plane, std::vector<Vector3d>* hull_out) {
    // In-plane coordinates (u, v), then Andrew's monotone chain.
    const Vector3d n = plane.normal.normalized();
    const Vector3d u = (std::abs(n.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY()).cross(n).normalized();
    const Vector3d v = n.cross(u);
    struct P {
        double x, y;
        std::size_t i;
    };
    std::vector<P> p;
    for (std::size_t i = 0; i < section.size(); ++i) {
        const Vector3d d = section[i] - plane.point;
        p.push_back({d.dot(u), d.dot(v), i});
    }
    if (hull_out) hull_out->clear();
    std::sort(p.begin(), p.end(), [](const P& a, const P& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    p.erase(std::unique(p.begin(), p.end(), [](const P& a, const P& b) { return a.x == b.x && a.y == b.y; }), p.end());
    if (p.size() < 3) return 0;
    auto cross = [](const P& o, const P& a, const P& b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); };
    std::vector<P> hull(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
        hull[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, lower = k + 1; i > 0; --i) {
        while (k >= lower && cross(hull[k - 2], hull[k - 1], p[i - 1]) <= 0) --k;
        hull[k++] = p[i - 1];
    }
    hull.resize(k - 1);
    double perimeter = 0;
    for (std::size_t i = 0; i < hull.size(); ++i) {
        const P& a = hull[i];
        const P& b = hull[(i + 1) % hull.size()];
        perimeter += std::hypot(b.x - a.x, b.y - a.y);
        if (hull_out) hull_out->push_back(section[a.i]);
    }
    return perimeter;
}

}  // namespace ssc::measure
