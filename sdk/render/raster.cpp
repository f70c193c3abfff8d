#include "raster.hpp"

#include "common/error.hpp"
#include "common/files.hpp"

#if SSCAPE_WITH_PNG
#include <png.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace ssc::render {
namespace {

// Screen position (pixels) and depth (larger = nearer the viewer) of a world point.
void project(const Viewport& vp, View view, const float* p, float& sx, float& sy, float& depth) {
    const float h = view == View::Front ? p[0] : view == View::Back ? -p[0] : -p[2];
    depth = view == View::Front ? p[2] : view == View::Back ? -p[2] : p[0];
    sx = vp.x0 + 0.5f * vp.width + (h - vp.centre_x) * vp.scale;
    sy = vp.y0 + 0.5f * vp.height - (p[1] - vp.centre_y) * vp.scale;
}

}  // namespace

void Image::set(int x, int y, uint8_t r, uint8_t g, uint8_t b) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    uint8_t* p = &rgb[(std::size_t(y) * width + x) * 3];
    p[0] = r;
    p[1] = g;
    p[2] = b;
}

void draw_mesh(Image& img, std::vector<float>& depth, const Viewport& vp, View view, const float* xyz,
               const uint32_t* tris, uint32_t count, const uint8_t colour[3], const uint8_t* triangle_colours) {
    depth.resize(std::size_t(img.width) * img.height, -1e30f);
    // Light from the upper front-left of the viewer.
    const float L[3] = {-0.35f, 0.5f, 0.79f};
    for (uint32_t t = 0; t < count; ++t) {
        const float* P[3] = {xyz + 3 * std::size_t(tris[3 * t]), xyz + 3 * std::size_t(tris[3 * t + 1]),
                             xyz + 3 * std::size_t(tris[3 * t + 2])};
        float sx[3], sy[3], sz[3];
        for (int i = 0; i < 3; ++i) project(vp, view, P[i], sx[i], sy[i], sz[i]);
        // Face normal in view space (screen x right, y up, z towards the viewer).
        float a[3], b[3];
        for (int i = 0; i < 3; ++i) {
            const float v1[3] = {P[1][0] - P[0][0], P[1][1] - P[0][1], P[1][2] - P[0][2]};
            const float v2[3] = {P[2][0] - P[0][0], P[2][1] - P[0][1], P[2][2] - P[0][2]};
            a[i] = v1[i];
            b[i] = v2[i];
        }
        float n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        if (view == View::Side) {  // view axes: right = -Z, up = Y, towards viewer = +X
            const float nx = -n[2], nz = n[0];
            n[0] = nx;
            n[2] = nz;
        } else if (view == View::Back) {  // right = -X, towards viewer = -Z
            n[0] = -n[0];
            n[2] = -n[2];
        }
        const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len <= 0) continue;
        const float lambert = std::max(0.f, (n[0] * L[0] + n[1] * L[1] + n[2] * L[2]) / len);
        const float shade = 0.25f + 0.75f * lambert;
        const int x0 = std::max(vp.x0, int(std::floor(std::min({sx[0], sx[1], sx[2]}))));
        const int x1 = std::min(vp.x0 + vp.width - 1, int(std::ceil(std::max({sx[0], sx[1], sx[2]}))));
        const int y0 = std::max(vp.y0, int(std::floor(std::min({sy[0], sy[1], sy[2]}))));
        const int y1 = std::min(vp.y0 + vp.height - 1, int(std::ceil(std::max({sy[0], sy[1], sy[2]}))));
        const float area = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sx[2] - sx[0]) * (sy[1] - sy[0]);
        if (std::abs(area) < 1e-12f) continue;
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const float px = x + 0.5f, py = y + 0.5f;
                const float w0 = ((sx[1] - px) * (sy[2] - py) - (sx[2] - px) * (sy[1] - py)) / area;
                const float w1 = ((sx[2] - px) * (sy[0] - py) - (sx[0] - px) * (sy[2] - py)) / area;
                const float w2 = 1.f - w0 - w1;
                if (w0 < 0 || w1 < 0 || w2 < 0) continue;
                const float z = w0 * sz[0] + w1 * sz[1] + w2 * sz[2];
                float& d = depth[std::size_t(y) * img.width + x];
                if (z <= d) continue;
                d = z;
                const uint8_t* c = triangle_colours ? triangle_colours + 3 * std::size_t(t) : colour;
                img.set(x, y, uint8_t(c[0] * shade), uint8_t(c[1] * shade), uint8_t(c[2] * shade));
            }
    }
}

void view_direction(View view, float out[3]) {
    out[0] = view == View::Side ? 1.f : 0.f;
    out[1] = 0.f;
    out[2] = view == View::Front ? 1.f : view == View::Back ? -1.f : 0.f;
}

void draw_point(Image& img, const Viewport& vp, View view, const float* p, int radius, const uint8_t colour[3]) {
    float sx, sy, sz;
    project(vp, view, p, sx, sy, sz);
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx)
            if (dx * dx + dy * dy <= radius * radius) img.set(int(sx) + dx, int(sy) + dy, colour[0], colour[1], colour[2]);
}

bool draw_visible_point(Image& img, const std::vector<float>& depth, const Viewport& vp, View view, const float* p,
                        int radius, const uint8_t colour[3], float tolerance) {
    float sx, sy, sz;
    project(vp, view, p, sx, sy, sz);
    const int x = int(sx), y = int(sy);
    if (x < vp.x0 || y < vp.y0 || x >= vp.x0 + vp.width || y >= vp.y0 + vp.height) return false;
    if (x >= img.width || y >= img.height || depth.empty()) return false;
    const float d = depth[std::size_t(y) * img.width + x];
    if (d < -1e29f || sz + tolerance < d) return false;  // off the mesh, or behind it
    draw_point(img, vp, view, p, radius, colour);
    return true;
}

#if SSCAPE_WITH_PNG
namespace {

void append_png(png_structp png, png_bytep data, png_size_t size) {
    auto* out = static_cast<std::string*>(png_get_io_ptr(png));
    try {
        out->append(reinterpret_cast<const char*>(data), size);
    } catch (...) {  // no C++ exception may unwind through libpng's C frames
        png_error(png, "out of memory");
    }
}

// libpng reports errors by longjmp: keep the setjmp frame free of locals that change after it.
bool encode_png(png_structp png, png_infop info, std::string* out, const Image& img) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_write_fn(png, out, append_png, nullptr);
    png_set_IHDR(png, info, img.width, img.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < img.height; ++y) png_write_row(png, const_cast<png_bytep>(&img.rgb[std::size_t(y) * img.width * 3]));
    png_write_end(png, nullptr);
    return true;
}

}  // namespace

void write_png(const std::string& path, const Image& img) {
    std::string bytes;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    const bool ok = png && info && encode_png(png, info, &bytes, img);
    png_destroy_write_struct(png ? &png : nullptr, info ? &info : nullptr);
    if (!ok) fail(SSC_ERROR_IO, "cannot encode PNG '" + path + "'");
    write_file_atomically(path, bytes.data(), bytes.size());
}

#else
void write_png(const std::string& path, const Image&) {
    fail(SSC_ERROR_IO, "cannot write '" + path + "': this build of sscape writes no PNG pictures (configured with SSCAPE_BUILD_PICTURES=OFF)");
}
#endif

}  // namespace ssc::render
