#include "simulation/depth_camera.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ssc::simulation {

using Eigen::Matrix3d;
using Eigen::Vector3d;

fitting::PinholeCamera look_at(const Vector3d& eye, const Vector3d& target, const DepthCameraSpec& spec) {
    fitting::PinholeCamera c;
    c.fx = c.fy = spec.focal;
    c.cx = 0.5 * (double(spec.width) - 1);
    c.cy = 0.5 * (double(spec.height) - 1);
    const Vector3d z = (target - eye).normalized();
    Vector3d up = Vector3d::UnitY();
    if (std::abs(z.dot(up)) > 0.99) up = Vector3d::UnitZ();
    const Vector3d x = z.cross(up).normalized();  // image right
    const Vector3d y = z.cross(x);                // image down
    c.rotation.col(0) = x;
    c.rotation.col(1) = y;
    c.rotation.col(2) = z;
    c.position = eye;
    return c;
}

std::vector<float> render_depth(const Model& m, const TrueBody& b, const fitting::PinholeCamera& cam, const DepthCameraSpec& spec,
                                std::mt19937& rng) {
    const int W = int(spec.width), H = int(spec.height);
    constexpr float kNone = std::numeric_limits<float>::infinity();
    std::vector<float> z(std::size_t(W) * std::size_t(H), kNone);
    const Matrix3d Rt = cam.rotation.transpose();
    std::vector<Vector3d> proj(b.vertices.size());  // pixel x, pixel y, depth
    for (std::size_t v = 0; v < b.vertices.size(); ++v) {
        const Vector3d p = Rt * (b.vertices[v] - cam.position);
        proj[v] = Vector3d(cam.fx * p.x() / p.z() + cam.cx, cam.fy * p.y() / p.z() + cam.cy, p.z());
    }
    const auto& tri = m.data().mesh.triangles;
    for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
        const Vector3d& a = proj[tri[t]];
        const Vector3d& bb = proj[tri[t + 1]];
        const Vector3d& c = proj[tri[t + 2]];
        if (a.z() < 0.05 || bb.z() < 0.05 || c.z() < 0.05) continue;  // behind or at the camera
        const double area = (bb.x() - a.x()) * (c.y() - a.y()) - (bb.y() - a.y()) * (c.x() - a.x());
        if (std::abs(area) < 1e-12) continue;
        const int x0 = std::max(0, int(std::ceil(std::min({a.x(), bb.x(), c.x()}))));
        const int x1 = std::min(W - 1, int(std::floor(std::max({a.x(), bb.x(), c.x()}))));
        const int y0 = std::max(0, int(std::ceil(std::min({a.y(), bb.y(), c.y()}))));
        const int y1 = std::min(H - 1, int(std::floor(std::max({a.y(), bb.y(), c.y()}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                // Barycentric coordinates in the image; 1/depth is linear there (perspective).
                const double w0 = ((bb.x() - x) * (c.y() - y) - (bb.y() - y) * (c.x() - x)) / area;
                const double w1 = ((c.x() - x) * (a.y() - y) - (c.y() - y) * (a.x() - x)) / area;
                const double w2 = 1 - w0 - w1;
                if (w0 < 0 || w1 < 0 || w2 < 0) continue;
                const double depth = 1.0 / (w0 / a.z() + w1 / bb.z() + w2 / c.z());
                float& d = z[std::size_t(y) * std::size_t(W) + std::size_t(x)];
                d = std::min(d, float(depth));
            }
    }
    std::normal_distribution<double> noise(0.0, spec.noise);
    for (float& d : z) d = d == kNone ? 0.f : float(std::max(0.0, d + (spec.noise > 0 ? noise(rng) : 0.0)));
    return z;
}

fitting::PointCloud booth_scan(const Model& m, const TrueBody& b, const BoothSpec& spec, std::mt19937& rng) {
    Vector3d lo = Vector3d::Constant(1e30), hi = -lo;
    for (const Vector3d& v : b.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const Vector3d axis(0.5 * (lo.x() + hi.x()), 0, 0.5 * (lo.z() + hi.z()));
    fitting::PointCloud all;
    for (uint32_t c = 0; c < spec.columns; ++c) {
        const double a = spec.heading + 2 * M_PI * double(c) / double(spec.columns);
        for (double h : spec.heights) {
            const Vector3d eye = axis + Vector3d(spec.distance * std::sin(a), lo.y() + h, spec.distance * std::cos(a));
            const Vector3d target(axis.x(), lo.y() + h, axis.z());
            fitting::DepthView view;
            view.width = spec.camera.width, view.height = spec.camera.height;
            view.camera = look_at(eye, target, spec.camera);
            const std::vector<float> depth = render_depth(m, b, view.camera, spec.camera, rng);
            // A camera that sees (almost) nothing of the body, one above a crouching or lying
            // person, adds nothing.
            if (std::count_if(depth.begin(), depth.end(), [](float z) { return z > 0; }) < 64) continue;
            view.depth = depth.data();
            const fitting::PointCloud one = fitting::depth_to_cloud(view);
            all.points.insert(all.points.end(), one.points.begin(), one.points.end());
            all.normals.insert(all.normals.end(), one.normals.begin(), one.normals.end());
        }
    }
    if (spec.points == 0 || all.points.size() <= spec.points) return all;
    std::vector<uint32_t> order(all.points.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    fitting::PointCloud kept;
    for (uint32_t k = 0; k < spec.points; ++k) {
        kept.points.push_back(all.points[order[k]]);
        kept.normals.push_back(all.normals[order[k]]);
    }
    return kept;
}

}  // namespace ssc::simulation
