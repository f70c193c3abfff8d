#include "segment_picture.hpp"

#include "raster.hpp"
#include "text.hpp"

#include <algorithm>

namespace ssc::render {
namespace {

constexpr uint8_t kPalette[][3] = {{230, 180, 60}, {80, 150, 220}, {90, 190, 120}, {220, 110, 100}, {170, 120, 210}, {90, 200, 200}, {200, 200, 90}};

void bounds(const std::vector<float>& xyz, float lo[3], float hi[3]) {
    for (int a = 0; a < 3; ++a) lo[a] = 1e9f, hi[a] = -1e9f;
    for (std::size_t i = 0; i < xyz.size(); ++i) lo[i % 3] = std::min(lo[i % 3], xyz[i]), hi[i % 3] = std::max(hi[i % 3], xyz[i]);
}

}  // namespace

void write_segment_picture(const std::string& path, const std::vector<float>& mean, const std::vector<uint32_t>& tris,
                           const std::vector<SegmentView>& segments) {
    const int cell_w = 150, cell_h = 300, header = 30, label = 22;
    const int cells = 2 + 2 * int(segments.size());
    Image img(cells * cell_w, header + label + cell_h);
    const uint8_t ink[3] = {40, 40, 40}, skin[3] = {225, 190, 160};
    draw_text(img, 8, 8, "segments (front, back), then each segment's first component at -3 and +3 SD", 2, ink);
    const auto T = uint32_t(tris.size() / 3);
    // Each triangle in the blend of its corners' segment colours.
    std::vector<uint8_t> colours(3ull * T);
    for (uint32_t t = 0; t < T; ++t)
        for (int c = 0; c < 3; ++c) {
            float x = 0;
            for (std::size_t s = 0; s < segments.size(); ++s) {
                float w = 0;
                for (int corner = 0; corner < 3; ++corner) w += segments[s].weight[tris[3 * t + corner]] / 3;
                x += w * kPalette[s % 7][c];
            }
            colours[3 * t + c] = uint8_t(std::clamp(x, 0.f, 255.f));
        }
    // One scale and one vertical centre for every body, so that lengths compare across the cells.
    float lo[3], hi[3];
    bounds(mean, lo, hi);
    for (const auto& s : segments)
        for (const auto* xyz : {&s.minus, &s.plus}) {
            float blo[3], bhi[3];
            bounds(*xyz, blo, bhi);
            lo[1] = std::min(lo[1], blo[1]), hi[1] = std::max(hi[1], bhi[1]);
        }
    const float scale = 0.9f * cell_h / std::max(0.5f, hi[1] - lo[1]);
    auto draw = [&](int cell, const std::vector<float>& xyz, View view, const uint8_t* triangle_colours) {
        float blo[3], bhi[3];
        bounds(xyz, blo, bhi);
        std::vector<float> depth;
        const Viewport vp{cell * cell_w, header + label, cell_w, cell_h, view == View::Side ? -0.5f * (blo[2] + bhi[2]) : 0.5f * (blo[0] + bhi[0]),
                          0.5f * (lo[1] + hi[1]), scale};
        draw_mesh(img, depth, vp, view, xyz.data(), tris.data(), T, skin, triangle_colours);
    };
    draw(0, mean, View::Front, colours.data());
    draw(1, mean, View::Back, colours.data());
    for (std::size_t s = 0; s < segments.size(); ++s) {
        const int cell = 2 + 2 * int(s);
        draw_text(img, cell * cell_w + 8, header + 2, segments[s].name, 2, kPalette[s % 7]);
        draw(cell, segments[s].minus, View::Front, nullptr);
        draw(cell + 1, segments[s].plus, View::Front, nullptr);
    }
    write_png(path, img);
}

}  // namespace ssc::render
