// Readers for measurement files the fitter takes: CAESAR .lnd landmark files, PLY and OBJ point
// clouds or meshes, 16-bit PGM depth images. Each validates what it reads and throws
// ssc::Error (SSC_ERROR_IO for unreadable files, SSC_ERROR_INVALID_ARGUMENT for malformed content)
// with the file name and line or offset.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ssc::io {

struct LandmarkRecord {
    uint32_t index = 0;          // the file's 1-based landmark number
    std::string name;            // as written in the file
    Eigen::Vector3d position;    // metres (the file's millimetres / 1000), the file's frame
};

// CAESAR .lnd: header lines, then rows between "AUX =" and "END =". Rows whose status columns hold
// -999 (landmark not found) are skipped.
std::vector<LandmarkRecord> read_lnd(const std::string& path);

struct PointFile {
    std::vector<Eigen::Vector3d> points;   // in the file's units (the caller scales)
    std::vector<Eigen::Vector3d> normals;  // empty, or one per point: unit, or zero where unknown
};

// PLY (ascii or binary little/big endian; x y z, optional nx ny nz; faces give normals when the
// file has none) and OBJ (v lines, optional vn per vertex or f lines for normals). By extension.
// The result holds at least one point, and either no normals or one per point: a finite unit
// normal, or zero where the file gives none usable for that point (a zero or non-finite normal,
// a point on no face); the fitter estimates those.
PointFile read_points(const std::string& path);

// The most bytes an input file may hold (2 GiB): a larger one is refused, not half read.
constexpr std::size_t kMaxInputBytes = std::size_t(2) << 30;

struct DepthImage {
    uint32_t width = 0, height = 0;
    std::vector<float> depth;  // metres, row-major from the top; 0 = no measurement
    // The camera, when the file's header comments give it (sscape simulate writes them):
    //   # sscape intrinsics FX FY CX CY            pinhole, pixels
    //   # sscape camera_to_world M0 ... M15        column-major 4x4, camera frame x right, y down, z forward
    bool has_intrinsics = false, has_pose = false;
    double fx = 0, fy = 0, cx = 0, cy = 0;
    Eigen::Matrix4d camera_to_world = Eigen::Matrix4d::Identity();
};

// Binary PGM (P5) with maxval > 255 (16-bit big-endian samples), values in millimetres; the camera
// comments above are read when present (malformed ones are an error, other comments are ignored).
DepthImage read_pgm_depth(const std::string& path);

// The same readers over bytes already in memory (what the fuzz targets call); `name` stands for
// the file in messages.
std::vector<LandmarkRecord> parse_lnd(const std::string& data, const std::string& name);
PointFile parse_ply(const std::string& data, const std::string& name);
PointFile parse_obj(const std::string& data, const std::string& name);
PointFile parse_points(const std::string& data, const std::string& name);  // by name's extension, as read_points
DepthImage parse_pgm_depth(const std::string& data, const std::string& name);

// Landmark names compared as the CAESAR files spell them: case, spaces and punctuation ignored
// ("Lt. Metacarpal-Phal. II" == "lt metacarpal phal ii").
std::string normalized_landmark_name(const std::string& name);

}  // namespace ssc::io
