#include "render/registration_picture.hpp"

#include "render/raster.hpp"
#include "render/text.hpp"

#include <algorithm>

namespace ssc::render {

namespace {

// Green (0) to yellow (5 mm) to red (10 mm and beyond); grey for none.
void error_colour(double e, uint8_t out[3]) {
    if (e < 0) {
        out[0] = out[1] = out[2] = 170;
        return;
    }
    const double t = std::min(1.0, e / 0.010);
    out[0] = uint8_t(t < 0.5 ? 60 + 2 * t * 180 : 240);
    out[1] = uint8_t(t < 0.5 ? 200 : 200 - (t - 0.5) * 2 * 170);
    out[2] = 60;
}

}  // namespace

void write_registration_picture(const std::string& path, const Model& model, const Eigen::Matrix3d& frame_R,
                                const Eigen::Vector3d& frame_t, const std::vector<Eigen::Vector3d>& points,
                                const std::vector<Eigen::Vector3d>& registered, const std::vector<double>& error) {
    auto packed = [&](const std::vector<Eigen::Vector3d>& v) {
        std::vector<float> out;
        out.reserve(3 * v.size());
        for (const auto& p : v) {
            const Eigen::Vector3d c = frame_R.transpose() * (p - frame_t);
            out.insert(out.end(), {float(c.x()), float(c.y()), float(c.z())});
        }
        return out;
    };
    const std::vector<float> rv = packed(registered), pv = packed(points);
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (std::size_t i = 0; i < rv.size(); ++i) lo[i % 3] = std::min(lo[i % 3], rv[i]), hi[i % 3] = std::max(hi[i % 3], rv[i]);
    const auto& tris = model.data().mesh.triangles;
    const uint32_t T = uint32_t(tris.size() / 3);
    std::vector<uint8_t> colours(3 * std::size_t(T));
    for (uint32_t t = 0; t < T; ++t) {
        double e = 0;
        bool none = false;
        for (int k = 0; k < 3; ++k) {
            const double x = error[tris[3 * std::size_t(t) + std::size_t(k)]];
            none |= x < 0;
            e += x / 3;
        }
        error_colour(none ? -1 : e, &colours[3 * std::size_t(t)]);
    }
    const int cell_h = 640, cell_w = 360;
    Image img(4 * cell_w, cell_h + 24);
    std::vector<float> depth;
    const uint8_t dot[3] = {200, 40, 40}, ink[3] = {40, 40, 40};
    const float scale = 0.92f * cell_h / std::max(hi[1] - lo[1], 1e-3f);
    for (int col = 0; col < 2; ++col)
        for (int view = 0; view < 2; ++view) {
            Viewport vp;
            vp.x0 = (2 * col + view) * cell_w;
            vp.y0 = 24;
            vp.width = cell_w;
            vp.height = cell_h;
            vp.centre_x = view == 0 ? 0.5f * (lo[0] + hi[0]) : -0.5f * (lo[2] + hi[2]);
            vp.centre_y = 0.5f * (lo[1] + hi[1]);
            vp.scale = scale;
            const View v = view == 0 ? View::Front : View::Side;
            if (col == 0) {
                const std::size_t n = pv.size() / 3, step = std::max<std::size_t>(1, n / 40000);
                for (std::size_t i = 0; i < n; i += step) draw_point(img, vp, v, &pv[3 * i], 0, dot);
            } else {
                const uint8_t skin[3] = {225, 190, 160};
                draw_mesh(img, depth, vp, v, rv.data(), tris.data(), T, skin, colours.data());
            }
        }
    draw_text(img, 8, 6, "scan", 2, ink);
    draw_text(img, 2 * cell_w + 8, 6, "registration: green 0, yellow 5 mm, red 10 mm+, grey none", 2, ink);
    write_png(path, img);
}

}  // namespace ssc::render
