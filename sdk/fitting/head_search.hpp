// The fitter's search over how the head is turned, after the fine stage.
//
// Why: a head is nearly round, so the fine stage's short correspondences hold it wherever the
// coarse stages left it: fits of people bending sideways, reaching or lying ended with the head
// tipped or turned 20 to 40 degrees from the person's while sitting on the scan (head vertices
// 25 to 75 mm off, a third of the mesh's vertices; docs/fitting.md). The face, the chin and the
// neck's line tell the turn apart once candidates far enough apart are scored: the neck's and the
// head's three anatomical angles, a grid of turns shared by both then a pattern search over all six, each
// scored with the explained measure of the head alone (LimbScore of the neck joint); a turn must
// gain kMinGain (head_search.cpp) to replace the fit's.
#pragma once

#include "common/thread_pool.hpp"
#include "fitting/explained.hpp"
#include "fitting/kinematics.hpp"
#include "synthesis/body.hpp"

#include <cstdint>
#include <vector>

namespace ssc::fitting {

// Searches the head of one frame and sets the chosen neck and head rotations. kin and body:
// scratch for the frame's model (their state is overwritten). Returns whether the head was turned.
// Rigs without two limited head joints (the neck and the head) are left as they are.
bool search_head(Kinematics& kin, Body& body, FitState& state, const CloudView& cloud, const std::vector<uint32_t>& vertex_sample,
                 ThreadPool& pool);

}  // namespace ssc::fitting
