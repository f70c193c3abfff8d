#include "render/measure_picture.hpp"

#include "render/raster.hpp"

#include <algorithm>
#include <cmath>

namespace ssc::render {

void write_measurement_picture(const std::string& path, const std::vector<float>& xyz, const std::vector<uint32_t>& tris,
                               const std::vector<measure::Path>& paths) {
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (std::size_t i = 0; i < xyz.size(); ++i) lo[i % 3] = std::min(lo[i % 3], xyz[i]), hi[i % 3] = std::max(hi[i % 3], xyz[i]);
    const int cell_h = 900;
    const float scale = 0.94f * cell_h / std::max(hi[1] - lo[1], 1e-3f);
    const int cell_w = int(scale * (std::max(hi[0] - lo[0], hi[2] - lo[2]) + 0.2f));  // room for the height lines
    Image img(3 * cell_w, cell_h);
    std::vector<float> depth;
    const uint8_t skin[3] = {225, 200, 180};
    // Alternating strong colours, so neighbouring loops (chest, underbust, waist) tell apart.
    const uint8_t palette[6][3] = {{200, 30, 30}, {30, 90, 200}, {20, 150, 60}, {200, 120, 0}, {140, 40, 170}, {0, 150, 160}};
    const View views[3] = {View::Front, View::Side, View::Back};
    for (int k = 0; k < 3; ++k) {
        Viewport vp{k * cell_w, 0, cell_w, cell_h, 0, 0.5f * (lo[1] + hi[1]), scale};
        vp.centre_x = views[k] == View::Front ? 0.5f * (lo[0] + hi[0]) : views[k] == View::Back ? -0.5f * (lo[0] + hi[0]) : -0.5f * (lo[2] + hi[2]);
        draw_mesh(img, depth, vp, views[k], xyz.data(), tris.data(), uint32_t(tris.size() / 3), skin);
        int heights = 0;
        for (std::size_t m = 0; m < paths.size(); ++m) {
            auto pts = paths[m].points;
            // Heights (a vertical segment) are drawn as dimension lines beside the body, in front of
            // everything, as on an anthropometric chart.
            const bool height = pts.size() == 2 && !paths[m].closed && std::abs(pts[0].x() - pts[1].x()) < 1e-9 &&
                                std::abs(pts[0].z() - pts[1].z()) < 1e-9;
            if (height) {
                const double off = 0.04 + 0.03 * heights++;
                for (auto& p : pts) p = Eigen::Vector3d(lo[0] - off, p.y(), hi[2] + off);
            }
            const std::size_t segments = paths[m].closed ? pts.size() : (pts.empty() ? 0 : pts.size() - 1);
            for (std::size_t s = 0; s < segments; ++s) {
                const Eigen::Vector3d a = pts[s], b = pts[(s + 1) % pts.size()];
                const int steps = std::max(1, int((b - a).norm() / 0.002));  // a dot every 2 mm
                for (int t = 0; t <= steps; ++t) {
                    const Eigen::Vector3d p = a + (b - a) * (double(t) / steps);
                    const float q[3] = {float(p.x()), float(p.y()), float(p.z())};
                    if (height) draw_point(img, vp, views[k], q, 1, palette[m % 6]);
                    else draw_visible_point(img, depth, vp, views[k], q, 2, palette[m % 6], 0.02f);
                }
            }
        }
    }
    write_png(path, img);
}

}  // namespace ssc::render
