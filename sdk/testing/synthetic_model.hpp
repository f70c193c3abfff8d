// Builds procedural models for tests, benchmarks and the demo until a trained model exists:
// a "capsule body" (one closed tube per bone around a humanoid or a tiny skeleton), smooth
// random shape components with decaying standard deviations, blended skin weights, a joint
// regressor over the ring of vertices around each joint, landmarks and vertex sets.
#pragma once

#include "sscape_format/model_data.hpp"
#include "sscape_format/model_io.hpp"

#include <cstdint>
#include <vector>

namespace ssc::testing {

enum class SyntheticSkeleton {
    Humanoid53,  // the 53-joint game-engine skeleton layout (root, pelvis, spine, arms, fingers, legs)
    Mini6,       // root, pelvis, spine, head, arm_l, arm_r
};

struct SyntheticSpec {
    SyntheticSkeleton skeleton = SyntheticSkeleton::Humanoid53;
    uint32_t vertex_count = 13380;        // met exactly
    uint32_t components = 50;
    uint32_t seed = 1;
    bool aligned_rest_orientations = true;  // bone frames with +Y along the bone; false = identity
    double tolerance = 1e-4;              // basis quantization tolerance, metres
};

struct SyntheticModel {
    format::ModelData data;           // quantized, ready to write
    std::vector<float> basis_float;   // the unquantized scaled basis (planar, metres per SD)
    format::QuantizeReport quantization;
};

SyntheticModel build_synthetic_model(const SyntheticSpec& spec);

}  // namespace ssc::testing
