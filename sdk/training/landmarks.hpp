// The 73 CAESAR anthropometric landmarks (shared/docs/landmarks.md), each placed on the template by
// an explicit anatomical rule: an extreme point of a body region, or where a ray from a joint (or
// from outside) in an anatomical direction meets the surface. Rules are written for a template in
// the model convention (metres, +Y up, facing +Z, the subject's left at +X, A-pose), using the
// regressed joints of the game-engine skeleton as anatomical anchors.
//
// Each rule's comment gives the definition it implements: the CAESAR survey's landmark descriptions
// as shared/docs/landmarks.md summarises them (ISO 8559-1 defines cervicale, acromion and bust point
// the same way), then how the rule finds that point on a mesh. Heights that anatomy gives as
// proportions are fractions of the template's stature. Rules revised after fits of real scans
// (issue 20) say what the old rule did and how far off it was.
#pragma once

#include "sscape_format/model_data.hpp"

#include <Eigen/Core>

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

// The template of a model's body: its rest vertices, the model's triangles, each vertex's dominant
// skin joint and the joints the model's regressor puts on those vertices.
LandmarkTemplate landmark_template(const format::ModelData& m, const float* rest_xyz);

// Where a landmark (a vertex, or a barycentric point of a triangle) lies on a surface xyz (3 per
// vertex) with the model's triangles.
Eigen::Vector3d landmark_position(const format::Landmark& l, const float* xyz, const uint32_t* triangles);

// The CAESAR names in CAESAR order (1-based order = index + 1).
const std::vector<std::string>& caesar_names();

// Places all 73 landmarks; throws ssc::Error if a rule finds no surface (a template that does not
// look like the one the rules were written for).
std::vector<format::Landmark> place_caesar_landmarks(const LandmarkTemplate& t);

}  // namespace ssc::training
