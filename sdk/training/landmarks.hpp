// The 73 CAESAR anthropometric landmarks (shared/docs/landmarks.md), each placed on the template by
// an explicit anatomical rule: an extreme point of a body region, or where a ray from a joint (or
// from outside) in an anatomical direction meets the surface. Rules are written for a template in
// the model convention (metres, +Y up, facing +Z, the subject's left at +X, A-pose), using the
// regressed joints of the game-engine skeleton as anatomical anchors.
#pragma once

#include "sscape_format/model_data.hpp"

#include <map>
#include <string>
#include <vector>

namespace ssc::training {

struct LandmarkTemplate {
    std::vector<float> xyz;                       // 3 per vertex
    std::vector<uint32_t> triangles;              // 3 per triangle
    std::vector<std::string> vertex_bone;         // dominant skin bone of each vertex
    std::map<std::string, std::vector<float>> joints;  // game bone name -> position (3 floats)
};

// The CAESAR names in CAESAR order (1-based order = index + 1).
const std::vector<std::string>& caesar_names();

// Places all 73 landmarks; throws ssc::Error if a rule finds no surface (a template that does not
// look like the one the rules were written for).
std::vector<format::Landmark> place_caesar_landmarks(const LandmarkTemplate& t);

}  // namespace ssc::training
