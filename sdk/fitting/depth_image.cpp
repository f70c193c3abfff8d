#include "fitting/depth_image.hpp"

#include "common/error.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstring>
#include <vector>

namespace ssc::fitting {

std::vector<float> depth_in_metres(const void* samples, uint32_t width, uint32_t height, std::size_t row_stride, DepthFormat format) {
    SSC_REQUIRE_ARG(samples != nullptr, "depth image: no samples");
    SSC_REQUIRE_ARG_S(width >= 5 && height >= 5 && width <= 16384 && height <= 16384,
                      "depth image: size " << width << " x " << height << " (5..16384 each)");
    const std::size_t sample = format == DepthFormat::U16Millimetres ? 2 : 4;
    const std::size_t stride = row_stride ? row_stride : sample * width;
    SSC_REQUIRE_ARG_S(stride >= sample * width && stride % sample == 0,
                      "depth image: row stride " << row_stride << " must be 0 or a multiple of " << sample << " >= " << sample * width);
    std::vector<float> depth(std::size_t(width) * height);
    const auto* base = static_cast<const unsigned char*>(samples);
    for (uint32_t v = 0; v < height; ++v) {
        const unsigned char* row = base + std::size_t(v) * stride;
        for (uint32_t u = 0; u < width; ++u) {
            float z;
            if (format == DepthFormat::U16Millimetres) {
                uint16_t mm;
                std::memcpy(&mm, row + 2 * std::size_t(u), 2);  // unaligned rows are allowed
                z = float(mm) * 1e-3f;
            } else {
                std::memcpy(&z, row + 4 * std::size_t(u), 4);
            }
            depth[std::size_t(v) * width + u] = z;
        }
    }
    return depth;
}

void validate_camera(const PinholeCamera& c) {
    SSC_REQUIRE_ARG_S(std::isfinite(c.fx) && std::isfinite(c.fy) && c.fx > 0 && c.fy > 0,
                      "camera: focal lengths must be positive (fx " << c.fx << ", fy " << c.fy << ")");
    SSC_REQUIRE_ARG_S(std::isfinite(c.cx) && std::isfinite(c.cy), "camera: principal point is not finite");
    SSC_REQUIRE_ARG(c.rotation.allFinite() && (c.rotation.transpose() * c.rotation - Matrix3d::Identity()).norm() < 1e-3 &&
                        c.rotation.determinant() > 0,
                    "camera: rotation is not a proper rotation matrix");
    SSC_REQUIRE_ARG(c.position.allFinite(), "camera: position is not finite");
}

PointCloud depth_to_cloud(const DepthView& img) {
    validate_camera(img.camera);
    SSC_REQUIRE_ARG(img.depth != nullptr, "depth image: no samples");
    SSC_REQUIRE_ARG_S(img.width >= 5 && img.height >= 5 && img.width <= 16384 && img.height <= 16384,
                      "depth image: size " << img.width << " x " << img.height << " (5..16384 each)");
    SSC_REQUIRE_ARG(std::isfinite(img.min_depth) && std::isfinite(img.max_depth) && img.min_depth >= 0 && img.max_depth >= 0,
                    "depth image: depth limits must be finite and >= 0");
    const PinholeCamera& cam = img.camera;
    const int W = int(img.width), H = int(img.height);
    const double far = img.max_depth > 0 ? img.max_depth : std::numeric_limits<double>::infinity();
    // Usable depths (0: none) and each column's and row's ray slope, found once: the window below
    // reads every pixel 25 times.
    std::vector<double> depth(std::size_t(W) * std::size_t(H), 0.0), ray_u(img.width), ray_v(img.height);
    for (std::size_t i = 0; i < depth.size(); ++i) {
        const float z = img.depth[i];
        if (z > 0 && std::isfinite(z) && (!img.mask || img.mask[i]) && z >= img.min_depth && z <= far) depth[i] = z;
    }
    for (int u = 0; u < W; ++u) ray_u[std::size_t(u)] = (u - cam.cx) / cam.fx;
    for (int v = 0; v < H; ++v) ray_v[std::size_t(v)] = (v - cam.cy) / cam.fy;
    auto depth_at = [&](int u, int v) { return depth[std::size_t(v) * std::size_t(W) + std::size_t(u)]; };
    auto camera_point = [&](int u, int v, double z) { return Vector3d(ray_u[std::size_t(u)] * z, ray_v[std::size_t(v)] * z, z); };
    PointCloud out;
    constexpr int R = 2;  // window radius: at 5 mm pixels, a 2.5 cm patch averages sensor noise
    for (int v = 0; v < H; ++v)
        for (int u = 0; u < W; ++u) {
            const double z0 = depth_at(u, v);
            if (z0 == 0) continue;
            const double jump = 0.03 + 0.02 * z0;
            // Moments about the pixel's own point: small numbers, so the covariance loses no precision.
            // Plain sums (x y z, then xx xy xz yy yz zz): Eigen's small temporaries here were most of
            // a booth scan's time under the sanitizers.
            const Vector3d p = camera_point(u, v, z0);
            double s[3] = {0, 0, 0}, o[6] = {0, 0, 0, 0, 0, 0};
            int n = 0;
            for (int dv = -R; dv <= R; ++dv)
                for (int du = -R; du <= R; ++du) {
                    const int uu = u + du, vv = v + dv;
                    if (uu < 0 || vv < 0 || uu >= W || vv >= H) continue;
                    const double z = depth_at(uu, vv);
                    if (z == 0 || std::abs(z - z0) > jump) continue;
                    const double dx = ray_u[std::size_t(uu)] * z - p.x(), dy = ray_v[std::size_t(vv)] * z - p.y(), dz = z - p.z();
                    s[0] += dx, s[1] += dy, s[2] += dz;
                    o[0] += dx * dx, o[1] += dx * dy, o[2] += dx * dz, o[3] += dy * dy, o[4] += dy * dz, o[5] += dz * dz;
                    ++n;
                }
            if (n < 6) continue;
            const Vector3d mean = Vector3d(s[0], s[1], s[2]) / n;
            Matrix3d outer;
            outer << o[0], o[1], o[2], o[1], o[3], o[4], o[2], o[4], o[5];
            const Matrix3d cov = outer / n - mean * mean.transpose();
            // The closed-form 3 x 3 solver: several times faster than the iterative one, and a
            // patch of 6 to 25 points needs no more.
            Eigen::SelfAdjointEigenSolver<Matrix3d> es;
            es.computeDirect(cov);
            Vector3d normal = es.eigenvectors().col(0);
            if (normal.dot(p) > 0) normal = -normal;  // towards the camera centre (the origin here)
            out.points.push_back(cam.rotation * p + cam.position);
            out.normals.push_back((cam.rotation * normal).normalized());
        }
    SSC_REQUIRE_ARG_S(out.points.size() >= 16, "depth image: " << out.points.size() << " usable pixels (at least 16 needed)");
    return out;
}

}  // namespace ssc::fitting
