#include "girth.hpp"

#include <algorithm>
#include <cmath>

namespace ssc::measure {

std::vector<double> horizontal_section(const float* xyz, const uint32_t* tris, std::size_t count,
                                       const std::vector<uint8_t>& allowed, double h) {
    std::vector<double> out;
    for (std::size_t t = 0; t < count; ++t) {
        const uint32_t* c = tris + 3 * t;
        if (!allowed.empty() && !(allowed[c[0]] && allowed[c[1]] && allowed[c[2]])) continue;
        for (int e = 0; e < 3; ++e) {
            const float* a = xyz + 3 * std::size_t(c[e]);
            const float* b = xyz + 3 * std::size_t(c[(e + 1) % 3]);
            const double da = a[1] - h, db = b[1] - h;
            if ((da < 0) == (db < 0)) continue;  // the edge does not cross the plane
            const double s = da / (da - db);
            out.push_back(a[0] + s * (b[0] - a[0]));
            out.push_back(a[2] + s * (b[2] - a[2]));
        }
    }
    return out;
}

double convex_perimeter(const std::vector<double>& xz) {
    // Andrew's monotone chain.
    std::vector<std::pair<double, double>> p;
    for (std::size_t i = 0; i + 1 < xz.size(); i += 2) p.emplace_back(xz[i], xz[i + 1]);
    if (p.size() < 3) return 0;
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
    if (p.size() < 3) return 0;
    auto cross = [](const auto& o, const auto& a, const auto& b) {
        return (a.first - o.first) * (b.second - o.second) - (a.second - o.second) * (b.first - o.first);
    };
    std::vector<std::pair<double, double>> hull(2 * p.size());
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
        const auto& a = hull[i];
        const auto& b = hull[(i + 1) % hull.size()];
        perimeter += std::hypot(b.first - a.first, b.second - a.second);
    }
    return perimeter;
}

double girth_at(const float* xyz, const uint32_t* tris, std::size_t count, const std::vector<uint8_t>& allowed, double h) {
    return convex_perimeter(horizontal_section(xyz, tris, count, allowed, h));
}

}  // namespace ssc::measure
