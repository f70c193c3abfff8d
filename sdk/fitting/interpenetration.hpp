// Whether a posed body passes through itself: how much of each forearm and lower leg lies deep
// inside another part (the trunk, the head, another limb).
//
// A person cannot put a forearm through their chest, but a fit can: on an all-round scan of arms
// held in front of the body (a boxing guard) a forearm placed inside the trunk leaves no scan point
// unexplained, because the trunk's surface explains what the arm's should (docs/fitting.md,
// "Judging a fit"). The same test keeps the benchmark's pose library to poses people can take.
//
// Only the distal part of each limb is tested (below the elbow and knee, hands and feet left out):
// upper arms and thighs press into the trunk in linear blend skinning wherever they meet it
// (arms at the sides of a heavy body, thighs against the belly in a squat), and fingers into
// whatever a hand rests on.
#pragma once

#include "fitting/judgement.hpp"
#include "fitting/kinematics.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace ssc::fitting {

// A vertex lies inside another part when it is this far behind that part's nearest surface
// (metres): soft tissue pressed together stays under it.
constexpr double kInsideDepth = 0.02;
// ... looked for within this distance (a forearm deeper inside the trunk is still near some of it).
constexpr double kInsideReach = 0.12;

struct LimbsInside {
    // Per region: the share of its tested (distal) vertices inside another part; 0 for the head
    // and trunk, which are not tested.
    std::array<double, kBodyRegionCount> share{};
    int32_t limb = -1;  // the region with the largest share, and the part it lies most inside (-1: none)
    int32_t part = -1;
    double worst = 0;   // share[limb]
};

class InterpenetrationTest {
public:
    // Which vertices are tested and which part each belongs to, from the model's skinning.
    explicit InterpenetrationTest(const LinearModel& lin);

    // The shares for a posed surface (every model vertex, with unit outward normals).
    LimbsInside measure(const std::vector<Vector3d>& vertices, const std::vector<Vector3d>& normals) const;

private:
    std::vector<uint8_t> regions_;                                  // per vertex (vertex_regions())
    std::vector<uint32_t> tested_;                                  // distal limb vertices, every few
    std::array<std::vector<uint32_t>, kBodyRegionCount> surface_;   // each part's vertices, every few
};

}  // namespace ssc::fitting
