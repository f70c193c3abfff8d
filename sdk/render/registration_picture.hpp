// Pictures of registrations: one registration beside its scan (`sscape register --png`), and the
// contact sheets of bootstrapping (many registrations per page, each marked accepted or rejected
// with the reason, for a person to review). The registered template is coloured by a per-vertex
// error: green within 1 mm, through yellow at 5 mm, to red at 10 mm and beyond; grey where there
// is none.
#pragma once

#include "fitting/kinematics.hpp"
#include "render/raster.hpp"
#include "synthesis/model.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace ssc::render {

// Where a registration is drawn from: upright and facing the viewer. world = R * picture + t, with
// R the fit's turn about the vertical only (a person stands upright in a scan) and t its translation.
struct PictureFrame {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
};
PictureFrame fit_picture_frame(const Model& model, const fitting::FitState& fit);

// The scan's points and the registration, each from the front (and, with side, also from the
// side), in the rectangle (x0, y0, width, height) of img: the scan's views fill its left half.
// error: per vertex, metres, or negative for none.
void draw_registration(Image& img, int x0, int y0, int width, int height, bool side, const Model& model, const PictureFrame& frame,
                       const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& registered,
                       const std::vector<double>& error);

// One registration beside its scan, front and side, as PNG. Throws ssc::Error on I/O.
void write_registration_picture(const std::string& path, const Model& model, const PictureFrame& frame,
                                const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& registered,
                                const std::vector<double>& error);

// One entry of a contact sheet: the scan, its registration, and the verdict on it.
struct SheetEntry {
    std::string name;
    bool accepted = false;
    std::string reason;  // why rejected (or a note); drawn under the pictures
    PictureFrame frame;
    std::vector<Eigen::Vector3d> points, registered;
    std::vector<double> error;
};

// One page of a contact sheet: the entries 4 per row (12 fit a page well), rejected ones framed in
// red with their reason, under a title line. Throws ssc::Error on I/O.
void write_contact_sheet(const std::string& path, const Model& model, const std::vector<SheetEntry>& entries, const std::string& title);

}  // namespace ssc::render
