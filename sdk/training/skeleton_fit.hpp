// The game-engine skeleton for a trained model: joint positions regressed from body vertices
// (learned over the population), skin weights mapped from the asset's default rig, and rest
// orientations from the asset's bones.
#pragma once

#include "makehuman/assets.hpp"
#include "pca.hpp"

#include <string>
#include <vector>

namespace ssc::training {

// Joint positions (the game bones' heads: means of the asset's joint vertices) of one generated
// body with all vertices (helpers included): 3 per bone, in game-rig order.
std::vector<float> game_joint_positions(const mh::Assets& a, const std::vector<float>& xyz);

// Joint positions (3 per joint) of a mesh (packed xyz) by a sparse regressor: offsets (J + 1) into
// vertices and weights, joint = sum weight * vertex.
std::vector<float> apply_regressor(const uint32_t* offsets, const uint32_t* vertices, const float* weights, std::size_t joints,
                                   const float* xyz);

struct Regressor {
    std::vector<uint32_t> offsets, vertices;
    std::vector<float> weights;
    double heldout_mean_error = 0, heldout_max_error = 0;  // metres, on bodies left out of the fit
    std::vector<double> joint_mean_error;                  // per joint, metres, held out
};

// Learns, per joint, weights over about `support` body vertices around it (the nearest in each of
// 6 directions, on the mean body), summing to 1, by ridge-regularised least squares over the bodies. bodies: N x 3V body vertices;
// joints: N x 3J. The last `heldout` bodies are kept out of the fit and measured.
Regressor learn_regressor(const SampleMatrix& bodies, const SampleMatrix& joints, uint32_t support = 24,
                          uint32_t heldout = 0);

// 4 influences per body vertex (joints into the game rig, weights normalised).
void game_skin_weights(const mh::Assets& a, std::vector<uint16_t>& joints, std::vector<float>& weights);

// Rest orientation (local to the parent) per game bone, xyzw: +Y along head->tail, then the
// asset's roll about it. xyz: a generated body with all vertices.
std::vector<float> game_rest_orientations(const mh::Assets& a, const std::vector<float>& xyz);

}  // namespace ssc::training
