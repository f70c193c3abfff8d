#include "render/registration_picture.hpp"

#include "common/axes.hpp"
#include "common/rigid.hpp"
#include "fitting/body_orientation.hpp"
#include "render/text.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

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

const uint8_t kInk[3] = {40, 40, 40};

}  // namespace

PictureFrame fit_picture_frame(const Model& model, const fitting::FitState& fit) {
    PictureFrame f;
    if (fit.pose.empty()) return f;
    // Drawn upright along the scan's axis nearest the fitted body's up (a scan written z-up, read as
    // y-up, stands), facing the viewer: the body's forward turned about that axis.
    const Eigen::Matrix3d body = fitting::fitted_body_orientation(model.data(), fit);
    const Eigen::Vector3d up = up_axis_rotation(nearest_axis_name(body.col(1))).transpose() * Eigen::Vector3d::UnitY();
    Eigen::Vector3d forward = body.col(2) - body.col(2).dot(up) * up;
    if (forward.norm() < 1e-6) forward = body.col(0).cross(up);  // facing straight along the axis: by its side
    forward.normalize();
    f.R.col(0) = up.cross(forward);
    f.R.col(1) = up;
    f.R.col(2) = forward;
    f.t = fit.translation;
    return f;
}

void draw_registration(Image& img, int x0, int y0, int width, int height, bool side, const Model& model, const PictureFrame& frame,
                       const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& registered,
                       const std::vector<double>& error) {
    auto packed = [&](const std::vector<Eigen::Vector3d>& v) {
        std::vector<float> out;
        out.reserve(3 * v.size());
        for (const auto& p : v) {
            const Eigen::Vector3d c = frame.R.transpose() * (p - frame.t);
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
    const int views = side ? 2 : 1, cell_w = width / (2 * views);
    std::vector<float> depth;
    const uint8_t dot[3] = {200, 40, 40}, skin[3] = {225, 190, 160};
    const float wide = std::max(hi[0] - lo[0], side ? hi[2] - lo[2] : 0.0f);
    const float scale = 0.92f * std::min(float(height) / std::max(hi[1] - lo[1], 1e-3f), float(cell_w) / std::max(wide, 1e-3f));
    for (int col = 0; col < 2; ++col)
        for (int view = 0; view < views; ++view) {
            Viewport vp;
            vp.x0 = x0 + (views * col + view) * cell_w;
            vp.y0 = y0;
            vp.width = cell_w;
            vp.height = height;
            vp.centre_x = view == 0 ? 0.5f * (lo[0] + hi[0]) : -0.5f * (lo[2] + hi[2]);
            vp.centre_y = 0.5f * (lo[1] + hi[1]);
            vp.scale = scale;
            const View v = view == 0 ? View::Front : View::Side;
            if (col == 0) {
                const std::size_t n = pv.size() / 3, step = std::max<std::size_t>(1, n / 40000);
                for (std::size_t i = 0; i < n; i += step) draw_point(img, vp, v, &pv[3 * i], 0, dot);
            } else {
                draw_mesh(img, depth, vp, v, rv.data(), tris.data(), T, skin, colours.data());
            }
        }
}

void write_registration_picture(const std::string& path, const Model& model, const PictureFrame& frame,
                                const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& registered,
                                const std::vector<double>& error) {
    const int cell_h = 640, cell_w = 360;
    Image img(4 * cell_w, cell_h + 24);
    draw_registration(img, 0, 24, 4 * cell_w, cell_h, true, model, frame, points, registered, error);
    draw_text(img, 8, 6, "scan", 2, kInk);
    draw_text(img, 2 * cell_w + 8, 6, "registration: green 0, yellow 5 mm, red 10 mm+, grey none", 2, kInk);
    write_png(path, img);
}

void write_contact_sheet(const std::string& path, const Model& model, const std::vector<SheetEntry>& entries, const std::string& title) {
    const int columns = 4, cell_w = 400, picture_h = 420, caption_h = 40, header_h = 30;
    const int count = int(entries.size()), rows = std::max(1, (count + columns - 1) / columns);
    Image img(columns * cell_w, header_h + rows * (picture_h + caption_h));
    draw_text(img, 8, 8, title + " - scan | registration (green 0, yellow 5 mm, red 10 mm+, grey none)", 2, kInk);
    const uint8_t red[3] = {210, 30, 30}, green[3] = {30, 140, 50};
    for (int i = 0; i < count; ++i) {
        const SheetEntry& e = entries[std::size_t(i)];
        const int x0 = (i % columns) * cell_w, y0 = header_h + (i / columns) * (picture_h + caption_h), y1 = y0 + picture_h + caption_h;
        if (!e.registered.empty()) draw_registration(img, x0, y0, cell_w, picture_h, false, model, e.frame, e.points, e.registered, e.error);
        if (!e.accepted)  // a red frame round a rejected registration
            for (int k = 0; k < 3; ++k) {
                for (int x = x0; x < x0 + cell_w; ++x) img.set(x, y0 + k, red[0], red[1], red[2]), img.set(x, y1 - 1 - k, red[0], red[1], red[2]);
                for (int y = y0; y < y1; ++y) img.set(x0 + k, y, red[0], red[1], red[2]), img.set(x0 + cell_w - 1 - k, y, red[0], red[1], red[2]);
            }
        draw_text(img, x0 + 8, y0 + picture_h + 4, e.name + (e.accepted ? ": accepted" : ": REJECTED"), 2, e.accepted ? green : red);
        // The reason, cut to the cell (the decisions file has it whole).
        std::string why = e.reason;
        while (!why.empty() && text_width(why, 1) > cell_w - 16) why.pop_back();
        draw_text(img, x0 + 8, y0 + picture_h + 24, why, 1, kInk);
    }
    write_png(path, img);
}

}  // namespace ssc::render
