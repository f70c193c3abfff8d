// Automatic inspection of a registration, so that bootstrapping can learn from good ones only
// (the reference paper inspected every registration by eye because a low mean error can hide a
// failed arm or hand). Each body region is judged on its own, and the mesh and the fitted
// skeleton are checked for what a distance to the scan cannot show: folded or stretched triangles
// and joint angles no person takes. docs/learning.md gives the figures the defaults come from.
#pragma once

#include "scan_files/registration_record.hpp"
#include "synthesis/model.hpp"

#include <map>
#include <string>
#include <vector>

namespace ssc::learning {

struct AcceptanceRules {
    // Per region: the share of its vertices within 20 mm of a compatible scan point, at least. Holes
    // and unseen parts (soles, armpits, between the fingers) lower it in good registrations too.
    double min_within = 0.6;
    std::map<std::string, double> min_within_by_region = {{"hands", 0.4}, {"feet", 0.5}};
    // Per region: the scan points nearest to it but farther than 20 mm, as a share of all scan
    // points, at most: the scan's parts that the registration does not follow (a limb gone astray).
    // A share of all points, not of the region's, so that a little clutter near a small or
    // half-unseen region (the feet) does not count against it.
    double max_unexplained = 0.01;
    // Triangles turned over (normal against the model fit's), and stretched or squashed (area
    // changed by more than `stretch` times against the model fit's): shares of all, at most.
    double max_folded = 0.002;
    double stretch = 4;
    double max_stretched = 0.001;
    // The fitted skeleton's joints beyond their anatomical limits by more than this (radians).
    double joint_margin = 0.26;  // 15 degrees
};

struct Inspection {
    bool accepted = false;
    std::vector<std::string> reasons;  // each failed check, in words with its figures
    double folded = 0, stretched = 0;  // shares of triangles
    double joint_excess = 0;           // radians beyond the limits, the worst joint
    std::string worst_joint;
};

// Judges a registration read back or just made (the record's per-region quality, registered
// vertices and model fit; without a fit only the regions are judged).
Inspection inspect_registration(const Model& model, const scan_files::RegistrationRecord& record, const AcceptanceRules& rules);

}  // namespace ssc::learning
