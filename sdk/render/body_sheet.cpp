#include "render/body_sheet.hpp"

#include "render/raster.hpp"
#include "render/text.hpp"

#include <algorithm>

namespace ssc::render {

namespace {

struct Box {
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    explicit Box(const std::vector<float>& v) {
        for (std::size_t i = 0; i < v.size(); ++i) lo[i % 3] = std::min(lo[i % 3], v[i]), hi[i % 3] = std::max(hi[i % 3], v[i]);
    }
};

}  // namespace

void write_body_sheet(const std::string& path, const std::vector<std::vector<float>>& bodies, const std::vector<uint32_t>& tris,
                      const std::vector<std::string>& captions, int per_row) {
    const int cell_h = 420, caption_h = captions.empty() ? 0 : text_height(2) + 8;
    const int n = static_cast<int>(bodies.size());
    per_row = std::max(1, per_row);
    const int cols = std::max(1, std::min(n, per_row)), rows = std::max(1, (n + per_row - 1) / per_row);
    float tallest = 0.f, widest = 0.f;  // widest over both views: x extent and z extent
    for (const auto& v : bodies) {
        const Box b(v);
        tallest = std::max(tallest, b.hi[1] - b.lo[1]);
        widest = std::max({widest, b.hi[0] - b.lo[0], b.hi[2] - b.lo[2]});
    }
    const float scale = 0.92f * cell_h / std::max(tallest, 1e-3f);
    const int cell_w = std::max(120, int(scale * widest) + 16);
    Image img(cols * 2 * cell_w, rows * (cell_h + caption_h));
    std::vector<float> depth;
    const uint8_t skin[3] = {225, 190, 160}, ink[3] = {40, 40, 40};
    for (int b = 0; b < n; ++b) {
        const auto& v = bodies[std::size_t(b)];
        const Box box(v);
        const int x0 = (b % per_row) * 2 * cell_w, y0 = (b / per_row) * (cell_h + caption_h);
        for (int view = 0; view < 2; ++view) {
            Viewport vp;
            vp.x0 = x0 + view * cell_w;
            vp.y0 = y0 + caption_h;
            vp.width = cell_w;
            vp.height = cell_h;
            vp.centre_x = view == 0 ? 0.5f * (box.lo[0] + box.hi[0]) : -0.5f * (box.lo[2] + box.hi[2]);
            vp.centre_y = 0.5f * (box.lo[1] + box.hi[1]);
            vp.scale = scale;
            draw_mesh(img, depth, vp, view == 0 ? View::Front : View::Side, v.data(), tris.data(), static_cast<uint32_t>(tris.size() / 3), skin);
        }
        if (std::size_t(b) < captions.size()) draw_text(img, x0 + 6, y0 + 4, captions[std::size_t(b)], 2, ink);
    }
    write_png(path, img);
}

}  // namespace ssc::render
