// Registering a raw body scan to the model's template: the template mesh deformed onto the scan,
// vertex for vertex, so that scans can be learned from (docs/registration.md).
//
// 1. Initialisation: `model` fits the model's shape and pose to the scan (fitting/solver.hpp) and
//    starts from the fitted body; `rigid` aligns the template's landmarks to the scan's (with
//    scale); `rbf` warps the template through its landmarks onto the scan's (rbf_warp.hpp).
// 2. Non-rigid deformation (nonrigid.hpp): per-vertex affine transforms, correspondences found
//    again every iteration, the stiffness relaxed round by round.
// 3. Quality (registration_quality.hpp).
#pragma once

#include "common/thread_pool.hpp"
#include "fitting/kinematics.hpp"
#include "fitting/observations.hpp"
#include "fitting/solver.hpp"
#include "registration/rbf_warp.hpp"
#include "registration/registration_quality.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ssc::registration {

using Eigen::Vector3d;

enum class Initialisation { Model, Rigid, Rbf };
enum class Schedule {
    Relaxed,   // the stiffness and landmark weights fall by kRelax each round until the stiffness has fallen by 1000
    Constant,  // the same rounds at the final weights throughout
};

// The fitter's defaults but for more scan points per iteration and a larger iteration budget:
// registration runs offline, and over the benchmark's 20 booth scans this fit starts the
// deformation 1.4 mm closer to the true bodies (8.28 against 9.70 mm) for 0.3 s more
// (docs/registration.md). More points alone left one test scan's arm short of its limb search.
inline fitting::FitOptions registration_fit() {
    fitting::FitOptions o;
    o.max_points = 12000;
    o.max_iterations = 120;
    // Segment coefficients cost 10 times a whole-body one's: with the prior at 1 they also bent
    // bodies the whole body's components hold (the benchmark's default scans: 6.10 to 6.98 mm);
    // at 10 most of the gain on bodies beyond the model remains (docs/registration.md).
    o.segment_prior = 10;
    o.keep_segments_always = true;
    // Landmarks weigh as if placed to 2 mm, whatever their real placement error: the scan's
    // thousands of points share the model's errors (a head turned to match a face the model cannot
    // make), so they outvote some 60 landmarks far beyond their count. At the fitter's 1 cm, one
    // booth scan's head ended 22 degrees turned against exact landmarks 21-37 mm off; at 2 mm
    // the benchmark's registrations with landmarks fell from 4.61 to 3.94 mm (exact), 4.89 to 4.33
    // (placed to 5 mm) and 5.49 to 5.06 mm (to 10 mm): landmarks beyond 2 sigmas count linearly
    // (fitting/data_term.hpp), so badly placed ones pull boundedly (docs/registration.md).
    o.landmark_sigma = 0.002;
    return o;
}

struct RegistrationOptions {
    Initialisation initialisation = Initialisation::Model;
    Schedule schedule = Schedule::Relaxed;
    double stiffness = 0.03;  // b at the first round (chosen on the benchmark: docs/registration.md)
    double landmarks = 10;   // c at the first round, relative to the data term's 1
    double gamma = 1;        // G's weight of the transforms' translation
    uint32_t max_iterations = 4;  // solves per round at most (correspondences found again before each)
    RbfKernel rbf_kernel = RbfKernel::ThinPlate;  // the rbf start's kernel
    double rbf_scale = 0.1;                       // metres: its multiquadric or Gaussian scale
    fitting::FitOptions fit = registration_fit();  // the model fit of the `model` initialisation
    // The model's segment shape spaces (when it has them) join that fit, but for those left out
    // (Registrar; a caller of register_scan decides by its LinearModel): for bodies whose
    // proportions the whole body's components cannot hold, as real people's are. On by default:
    // on bodies beyond the model they cut the correspondence error by a third; on the model's own
    // bodies they cost a little (docs/registration.md). The head's is left out: on the benchmark it
    // slid the face along the surface.
    bool segments = true;
    std::vector<std::string> segments_left_out = {"head"};
    // Scans with more points are registered from an even subsample of this many (kMaxScanPoints,
    // below: the memory bound); at least 1000.
    std::size_t max_scan_points = 2000000;
};

// One region's correspondence rules (by the model's vertex sets; docs/registration.md).
struct RegionRule {
    double max_distance;  // metres
    double max_angle;     // degrees between the vertex's and the scan point's normals
    double data_weight;   // the data term's weight on the region's vertices
    double stiffness;     // multiplies the smoothness of the region's edges
};
RegionRule region_rule(const std::string& region);

struct RegistrationReport {
    double seconds = 0, fit_seconds = 0;
    uint32_t rounds = 0, solves = 0;
    std::size_t valid = 0;  // template vertices that ended on a compatible scan point
    std::size_t scan_points = 0, landmarks = 0;  // what it was registered to (at most kMaxScanPoints points)
    std::size_t scan_points_given = 0;           // the scan's points before thinning
    std::size_t deformation_landmarks = 0;       // of those, the ones the deformation pulled (register_scan.cpp)
    RegistrationQuality quality;
};

struct Registration {
    std::vector<Vector3d> vertices;  // the template, deformed onto the scan (model vertex order)
    std::vector<uint8_t> valid;      // per vertex: it ended on a compatible scan point
    fitting::FitSolution fit;        // the model fit that initialised it (`model`; empty otherwise)
    RegistrationReport report;
};

// The scan: points (metres), their normals (empty, or unit or zero per point: estimated where
// zero), its triangles when it is a mesh (empty for a cloud), and named landmarks on it.
struct Scan {
    fitting::PointCloud cloud;
    std::vector<uint32_t> triangles;
    std::vector<fitting::LandmarkTarget> landmarks;
};

// The most scan points a registration uses by default: a larger scan is registered from an even
// subsample of this many (every n/kMaxScanPoints-th point, its normals with them; its triangles left out, the
// hole rims then found from the points), so memory stays bounded: a registration holds about 350
// bytes a point (1,000,000 points: 465 MB peak), and 10 million once took 3.4 GB. Real booth
// scanners give 0.3 to 5 million points; 2 million hold more detail than the template's 13,380
// vertices can take.
constexpr std::size_t kMaxScanPoints = 2000000;  // RegistrationOptions::max_scan_points' default

// Stage names for progress: "fit", "deform" (done = round, total = rounds). Return false to cancel
// (ssc::Error, CANCELLED).
using RegistrationProgress = std::function<bool(const char* stage, uint32_t done, uint32_t total)>;

// The checks of a scan before any work, in one place for every way in (the Registrar checks its scan
// as it is set, register_scan for direct callers): finite points and normals, at least 100,
// spread like a body, triangle indices in range. ssc::Error
// INVALID_ARGUMENT, the message prefixed "register:".
void check_scan(const fitting::PointCloud& cloud, const std::vector<uint32_t>& triangles);
// The options' checks, in one place likewise (the Registrar's as it is made): INVALID_ARGUMENT.
void check_options(const RegistrationOptions& options);

// Throws ssc::Error: INVALID_ARGUMENT for a scan check_scan refuses or bad options, an
// initialisation the input cannot serve (rigid without 3 landmarks, rbf without 4 that span
// space), or a scan the model cannot be fitted to; CANCELLED.
Registration register_scan(const fitting::LinearModel& lin, const Scan& scan, const RegistrationOptions& options,
                           const RegistrationProgress& progress = {}, ThreadPool* pool = nullptr);

// register_scan without check_scan and the landmark and option checks, for a caller that made them
// as its input was set (the Registrar): the scan is checked once.
Registration register_checked_scan(const fitting::LinearModel& lin, const Scan& scan, const RegistrationOptions& options,
                                   const RegistrationProgress& progress = {}, ThreadPool* pool = nullptr);

}  // namespace ssc::registration
