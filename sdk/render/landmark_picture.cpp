#include "render/landmark_picture.hpp"

#include "render/raster.hpp"

#include <algorithm>
#include <cmath>

namespace ssc::render {

void write_landmark_picture(const std::string& path, const std::vector<float>& xyz, const std::vector<uint32_t>& tris,
                            const std::vector<float>& landmarks) {
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (std::size_t i = 0; i < xyz.size(); ++i) lo[i % 3] = std::min(lo[i % 3], xyz[i]), hi[i % 3] = std::max(hi[i % 3], xyz[i]);
    const float H = hi[1] - lo[1];
    const int cell_h = 900, close_h = cell_h / 2;
    const float scale = 0.95f * cell_h / H;
    const int cell_w = int(scale * std::max(hi[0] - lo[0], hi[2] - lo[2])) + 20;
    // Close-ups: the head (the top 14 % of the body) and the trunk (45 to 85 % of stature), each
    // from the front and the side, centred on the vertices in that band.
    struct Band {
        float y0, y1, x = 0, z = 0;
    } bands[2] = {{hi[1] - 0.14f * H, hi[1]}, {lo[1] + 0.45f * H, lo[1] + 0.85f * H}};
    for (auto& b : bands) {
        float xl = 1e30f, xh = -1e30f, zl = 1e30f, zh = -1e30f;
        for (std::size_t v = 0; v + 2 < xyz.size(); v += 3)
            if (xyz[v + 1] >= b.y0 && xyz[v + 1] <= b.y1 && (&b == &bands[0] || std::abs(xyz[v]) < 0.25f * H))
                xl = std::min(xl, xyz[v]), xh = std::max(xh, xyz[v]), zl = std::min(zl, xyz[v + 2]), zh = std::max(zh, xyz[v + 2]);
        b.x = 0.5f * (xl + xh), b.z = 0.5f * (zl + zh);
    }
    Image img(3 * cell_w + 2 * close_h, cell_h);
    std::vector<float> depth;
    const uint8_t skin[3] = {225, 200, 180}, red[3] = {220, 20, 20};
    auto draw = [&](const Viewport& vp, View view) {
        draw_mesh(img, depth, vp, view, xyz.data(), tris.data(), uint32_t(tris.size() / 3), skin);
        for (std::size_t l = 0; l + 2 < landmarks.size(); l += 3) draw_visible_point(img, depth, vp, view, &landmarks[l], 4, red);
    };
    const View whole[3] = {View::Front, View::Back, View::Side};
    for (int k = 0; k < 3; ++k) {
        Viewport vp{k * cell_w, 0, cell_w, cell_h, 0, 0.5f * (lo[1] + hi[1]), scale};
        vp.centre_x = whole[k] == View::Front ? 0.5f * (lo[0] + hi[0]) : whole[k] == View::Back ? -0.5f * (lo[0] + hi[0]) : -0.5f * (lo[2] + hi[2]);
        draw(vp, whole[k]);
    }
    for (int b = 0; b < 2; ++b)
        for (int side = 0; side < 2; ++side) {
            const Band& band = bands[b];
            const float zoom = 0.92f * close_h / (band.y1 - band.y0);
            Viewport vp{3 * cell_w + side * close_h, b * close_h, close_h, close_h, side ? -band.z : band.x, 0.5f * (band.y0 + band.y1), zoom};
            draw(vp, side ? View::Side : View::Front);
        }
    write_png(path, img);
}

}  // namespace ssc::render
