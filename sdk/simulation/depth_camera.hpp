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

// A booth scanner: columns of depth cameras in a ring around the body, each column with cameras at
// several heights looking horizontally at the body's axis, their clouds merged and thinned to a
// point count. What they cannot see stays missing, as in real booths: armpits, crotch, soles, the
// top of the head.
struct BoothSpec {
    uint32_t columns = 4;                   // around the body, evenly spaced
    std::vector<double> heights = {0.45, 1.30};  // metres above the body's lowest point
    double distance = 1.2;                  // metres from the body's vertical axis
    double heading = 0.3;                   // radians: where the first column stands
    DepthCameraSpec camera{640, 480, 525, 0.001};
    uint32_t points = 60000;                // kept of the merged cloud (a random subset); 0 = all
};
fitting::PointCloud booth_scan(const Model& m, const TrueBody& b, const BoothSpec& spec, std::mt19937& rng);

}  // namespace ssc::simulation
