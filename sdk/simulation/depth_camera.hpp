// A simulated depth camera: the first surface seen through each pixel centre of a pinhole camera
// (z-buffer rasterisation of the posed mesh, which equals ray casting at the pixel centres), with
// Gaussian noise along the ray direction's depth.
#pragma once

#include "fitting/depth_image.hpp"
#include "simulation/simulate.hpp"

namespace ssc::simulation {

struct DepthCameraSpec {
    uint32_t width = 640, height = 480;  // pixels
    double focal = 525;                  // pixels (a Kinect-class 640 x 480 sensor: about 62 x 49 degrees)
    double noise = 0.002;                // metres, standard deviation of each depth reading
};

// A camera at `eye` looking at `target` with the world's +y up in the image; intrinsics from spec
// (principal point at the image centre).
fitting::PinholeCamera look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const DepthCameraSpec& spec);

// Depth along the optical axis in metres, row-major from the top; 0 where no surface is seen.
std::vector<float> render_depth(const Model& m, const TrueBody& b, const fitting::PinholeCamera& camera,
                                const DepthCameraSpec& spec, std::mt19937& rng);

}  // namespace ssc::simulation
