// A scan collection with known truth, for testing and benchmarking learning from scans (CC0 data
// only): MakeHuman bodies of the training population with the head, neck and limb modifiers the
// default model was not trained on set at random (so no model of ours represents them exactly),
// standing in a booth scanner's pose with people's variation (simulation::scanning_pose), scanned
// by the simulated booth (simulation::booth_scan: 8 depth cameras, 1 mm noise, unseen parts left
// out). Also the same people's rest meshes, and more people's for held-out checks and weak starts.
#pragma once

#include "scan_files/scan_input.hpp"
#include "synthesis/model.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace ssc::testing {

struct CollectionSpec {
    uint32_t scans = 200;     // scanned people
    uint32_t extra = 100;     // further people, rest meshes only (held out, weak starts)
    uint32_t points = 30000;  // per scan
    double pose_spread = 10;  // degrees (simulation::scanning_pose)
    uint32_t seed = 2027;          // the population
    uint32_t variation_seed = 7;   // the modifiers beyond the model, the poses, the scanner's noise
    // Metres per axis, >= 0: each scan also gets its CAESAR landmarks (but the hands', which scanned
    // people's closed hands hide) as NAME.lnd beside it, placed with this Gaussian error, as
    // anthropometric collections come. Negative: none. Drawn apart, so the scans are the same
    // either way.
    double landmark_noise = -1;
};

struct SimulatedCollection {
    std::vector<scan_files::ScanInput> scans;                    // the scan files written, named b000, b001, ...
    std::vector<std::vector<Eigen::Vector3d>> truth;  // per scan: the true posed mesh (the scan's frame, metres)
    std::vector<std::vector<float>> poses;           // per scan: the pose it was given (xyzw per joint of `model`)
    std::vector<std::vector<Eigen::Vector3d>> rest;  // the scanned people's rest meshes, then the extra people's
};

// Writes the scans as PLY (points and normals, metres, +Y up) into `folder` (created), and their
// landmarks as .lnd (millimetres) when spec.landmark_noise >= 0. The people
// are posed with `model`'s skeleton and skinning (the template's topology). Throws ssc::Error: IO,
// or as training::mh::load_assets for a missing or broken asset folder.
SimulatedCollection simulate_collection(const std::string& makehuman, const Model& model, const CollectionSpec& spec, const std::string& folder);

}  // namespace ssc::testing
