#include "render/fit_picture.hpp"

#include "render/raster.hpp"

#include <algorithm>

namespace ssc::render {

void write_fit_picture(const std::string& path, const Model& model, const fitting::FitState& fit,
                       const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& fitted,
                       const std::vector<Eigen::Vector3d>& truth) {
    // Model frame of the fitted body: undo translation, scale and the root's rotation.
    const float* rq = &model.data().skeleton.rest_orientations[0];
    const Eigen::Matrix3d R0 = Eigen::Quaterniond(rq[3], rq[0], rq[1], rq[2]).normalized().toRotationMatrix();
    const Eigen::Matrix3d S0 = R0 * fit.pose[0].normalized().toRotationMatrix() * R0.transpose();
    auto canonical = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d { return S0.transpose() * ((p - fit.translation) / fit.scale); };
    auto packed = [&](const std::vector<Eigen::Vector3d>& v) {
        std::vector<float> out;
        out.reserve(3 * v.size());
        for (const auto& p : v) {
            const Eigen::Vector3d c = canonical(p);
            out.insert(out.end(), {float(c.x()), float(c.y()), float(c.z())});
        }
        return out;
    };
    const std::vector<float> fv = packed(fitted), tv = packed(truth), pv = packed(points);
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (std::size_t i = 0; i < fv.size(); ++i) lo[i % 3] = std::min(lo[i % 3], fv[i]), hi[i % 3] = std::max(hi[i % 3], fv[i]);
    const int cell_h = 640, cell_w = 360;
    const int columns = truth.empty() ? 2 : 3;
    Image img(columns * 2 * cell_w, cell_h);
    std::vector<float> depth;
    const auto& tris = model.data().mesh.triangles;
    const uint8_t skin[3] = {225, 190, 160}, truth_colour[3] = {170, 200, 230}, dot[3] = {200, 40, 40};
    // The body's height fills a cell, or its width or depth when wider (a body bent double or
    // lying: the front and side views drew over each other).
    const float wide = std::max(hi[0] - lo[0], hi[2] - lo[2]);
    const float scale = 0.92f * std::min(cell_h / std::max(hi[1] - lo[1], 1e-3f), cell_w / std::max(wide, 1e-3f));
    for (int col = 0; col < columns; ++col)
        for (int view = 0; view < 2; ++view) {
            Viewport vp;
            vp.x0 = (2 * col + view) * cell_w;
            vp.y0 = 0;
            vp.width = cell_w;
            vp.height = cell_h;
            vp.centre_x = view == 0 ? 0.5f * (lo[0] + hi[0]) : -0.5f * (lo[2] + hi[2]);
            vp.centre_y = 0.5f * (lo[1] + hi[1]);
            vp.scale = scale;
            const View v = view == 0 ? View::Front : View::Side;
            if (col == 0) {
                // The input: every point as a dot (at most 20k drawn).
                const std::size_t n = pv.size() / 3, step = std::max<std::size_t>(1, n / 20000);
                const int radius = n < 500 ? 3 : 1;  // landmarks big, scan points small
                for (std::size_t i = 0; i < n; i += step) draw_point(img, vp, v, &pv[3 * i], radius, dot);
            } else {
                const std::vector<float>& mesh = col == 1 ? fv : tv;
                draw_mesh(img, depth, vp, v, mesh.data(), tris.data(), uint32_t(tris.size() / 3), col == 1 ? skin : truth_colour);
            }
        }
    write_png(path, img);
}

}  // namespace ssc::render
