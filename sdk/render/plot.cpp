#include "render/plot.hpp"

#include "common/error.hpp"
#include "render/raster.hpp"
#include "render/text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ssc::render {

namespace {

constexpr int kWidth = 640, kHeight = 420;
constexpr int kLeft = 78, kRight = 24, kTop = 58, kBottom = 56;  // plot area margins
const uint8_t kInk[3] = {30, 30, 30}, kGrid[3] = {222, 222, 222};
// The curves' colours, the first the single curve's.
const uint8_t kLines[][3] = {{40, 90, 170}, {210, 90, 40}, {60, 150, 70}, {150, 60, 160}, {120, 120, 120}, {200, 160, 20}};

// A round tick step giving about `ticks` intervals over span: 1, 2 or 5 times a power of ten.
double nice_step(double span, int ticks) {
    const double raw = span / ticks, power = std::pow(10.0, std::floor(std::log10(raw)));
    for (const double m : {1.0, 2.0, 5.0})
        if (raw <= m * power) return m * power;
    return 10 * power;
}

std::string label(double v, double step) {
    char text[32];
    const int decimals = step >= 1 ? 0 : int(std::ceil(-std::log10(step) - 1e-9));
    std::snprintf(text, sizeof text, "%.*f", decimals, std::abs(v) < step * 1e-6 ? 0.0 : v);
    return text;
}

void dot(Image& img, int x, int y, int r, const uint8_t c[3]) {
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx)
            if (dx * dx + dy * dy <= r * r) img.set(x + dx, y + dy, c[0], c[1], c[2]);
}

// A line `width` pixels wide: discs stepped along it.
void line(Image& img, double x0, double y0, double x1, double y1, int width, const uint8_t c[3]) {
    const int steps = std::max(1, int(std::ceil(std::max(std::abs(x1 - x0), std::abs(y1 - y0)))));
    for (int i = 0; i <= steps; ++i) {
        const double t = double(i) / steps;
        dot(img, int(std::lround(x0 + t * (x1 - x0))), int(std::lround(y0 + t * (y1 - y0))), width / 2, c);
    }
}

}  // namespace

void write_line_plot(const std::string& path, const LinePlot& p) {
    std::vector<LineSeries> curves = {{p.name, p.x, p.y}};
    curves.insert(curves.end(), p.more.begin(), p.more.end());
    SSC_REQUIRE_ARG(curves.size() <= std::size(kLines), "plot: at most 6 curves");
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const LineSeries& c : curves) {
        SSC_REQUIRE_ARG(!c.x.empty() && c.x.size() == c.y.size(), "plot: one y value per x value, at least one");
        for (std::size_t i = 0; i < c.x.size(); ++i) {
            SSC_REQUIRE_ARG(std::isfinite(c.x[i]) && std::isfinite(c.y[i]), "plot: values must be finite");
            x0 = std::min(x0, c.x[i]), x1 = std::max(x1, c.x[i]), y0 = std::min(y0, c.y[i]), y1 = std::max(y1, c.y[i]);
        }
    }
    if (x1 - x0 <= 0) x0 -= 1, x1 += 1;
    if (y1 - y0 <= 0) y0 -= std::max(1e-9, std::abs(y0) * 0.1), y1 += std::max(1e-9, std::abs(y1) * 0.1);
    const double xs = nice_step(x1 - x0, 8), ys = nice_step(y1 - y0, 6);
    x0 = std::floor(x0 / xs) * xs, x1 = std::ceil(x1 / xs) * xs;
    y0 = std::floor(y0 / ys) * ys, y1 = std::ceil(y1 / ys) * ys;
    const int w = kWidth - kLeft - kRight, h = kHeight - kTop - kBottom;
    auto px = [&](double x) { return kLeft + (x - x0) / (x1 - x0) * w; };
    auto py = [&](double y) { return kTop + h - (y - y0) / (y1 - y0) * h; };

    Image img(kWidth, kHeight);
    for (double x = x0; x <= x1 + xs * 1e-6; x += xs) {
        line(img, px(x), kTop, px(x), kTop + h, 1, kGrid);
        const std::string t = label(x, xs);
        draw_text(img, int(px(x)) - text_width(t, 1) / 2, kTop + h + 8, t, 1, kInk);
    }
    for (double y = y0; y <= y1 + ys * 1e-6; y += ys) {
        line(img, kLeft, py(y), kLeft + w, py(y), 1, kGrid);
        const std::string t = label(y, ys);
        draw_text(img, kLeft - 8 - text_width(t, 1), int(py(y)) - 3, t, 1, kInk);
    }
    line(img, kLeft, kTop, kLeft, kTop + h, 1, kInk);
    line(img, kLeft, kTop + h, kLeft + w, kTop + h, 1, kInk);
    for (std::size_t k = 0; k < curves.size(); ++k) {
        const LineSeries& c = curves[k];
        for (std::size_t i = 1; i < c.x.size(); ++i) line(img, px(c.x[i - 1]), py(c.y[i - 1]), px(c.x[i]), py(c.y[i]), 3, kLines[k]);
        for (std::size_t i = 0; i < c.x.size(); ++i) dot(img, int(std::lround(px(c.x[i]))), int(std::lround(py(c.y[i]))), 4, kLines[k]);
    }
    if (curves.size() > 1)  // the legend, in the plot's lower right
        for (std::size_t k = 0; k < curves.size(); ++k) {
            const int y = kTop + h - 14 * int(curves.size() - k) - 4, x = kLeft + w - 200;
            line(img, x, y + 3, x + 16, y + 3, 3, kLines[k]);
            draw_text(img, x + 22, y, curves[k].name, 1, kInk);
        }
    draw_text(img, (kWidth - text_width(p.title, 2)) / 2, 10, p.title, 2, kInk);
    draw_text(img, kLeft, kTop - 16, p.y_label, 1, kInk);
    draw_text(img, kLeft + (w - text_width(p.x_label, 1)) / 2, kHeight - 20, p.x_label, 1, kInk);
    write_png(path, img);
}

}  // namespace ssc::render
