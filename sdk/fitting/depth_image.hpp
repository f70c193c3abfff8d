// Depth images as point clouds for the fitter: back-projection through a pinhole camera into the
// world frame, with a normal per pixel estimated from its image neighbourhood and turned towards
// the camera (a camera sees the outside of the surface, so that is the outward normal).
#pragma once

#include "fitting/observations.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ssc::fitting {

using Eigen::Matrix3d;

// A pinhole camera without lens distortion. Camera frame as in OpenCV: x right, y down, z forward
// (the optical axis); a pixel (u, v) with depth z is the camera point
// ((u - cx) z / fx, (v - cy) z / fy, z), pixel centres at integer coordinates.
struct PinholeCamera {
    double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
    Matrix3d rotation = Matrix3d::Identity();  // camera to world: world = rotation * camera + position
    Vector3d position = Vector3d::Zero();      // metres: the camera centre in the world
};

struct DepthView {
    uint32_t width = 0, height = 0;
    const float* depth = nullptr;     // width * height, row-major from the top: metres along the optical
                                      // axis; <= 0 or not finite = no measurement
    const uint8_t* mask = nullptr;    // NULL or width * height bytes: 0 = ignore the pixel (background)
    PinholeCamera camera;
    double min_depth = 0, max_depth = 0;  // metres: readings outside are ignored; max 0 = no limit
};

// How a depth camera stores its samples.
enum class DepthFormat { U16Millimetres, F32Metres };

// A depth image's samples as DepthView::depth wants them: width * height packed floats in metres.
// Rows lie row_stride bytes apart (0: packed). Throws ssc::Error(SSC_ERROR_INVALID_ARGUMENT) for a
// size outside 5 .. 16384 per side or a stride that is shorter than a row or not a multiple of the
// sample size.
std::vector<float> depth_in_metres(const void* samples, uint32_t width, uint32_t height, std::size_t row_stride, DepthFormat format);

// Throws ssc::Error(SSC_ERROR_INVALID_ARGUMENT) for degenerate intrinsics (focal lengths not
// positive, centre not finite), a rotation that is not orthonormal, or a non-finite position.
void validate_camera(const PinholeCamera& camera);

// The measured pixels as world points with unit normals facing the camera. A pixel keeps its point
// when at least 6 of its 5 x 5 neighbours lie on the same surface (depth within 3 cm + 2 %),
// which drops isolated readings and the mixed pixels at depth edges. Throws as validate_camera,
// and for an image without usable pixels.
PointCloud depth_to_cloud(const DepthView& image);

}  // namespace ssc::fitting
