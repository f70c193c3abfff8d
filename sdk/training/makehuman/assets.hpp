// Reading the CC0 MakeHuman assets (shared/makehuman; formats in its README.md) into plain arrays
// in metres. Nothing here knows about statistics: the population sampler and the trainer build on it.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace ssc::training::mh {

inline constexpr uint32_t kBodyVertices = 13380;  // the `body` group: vertices 0..13379
inline constexpr float kUnitToMetres = 0.1f;      // the assets are in decimetres

struct BaseMesh {
    uint32_t vertex_count = 0;        // all vertices, helpers included (joint cubes follow the shape)
    std::vector<float> xyz;           // 3 per vertex, metres
    std::vector<uint32_t> body_quads; // 4 per quad, the body group only
    std::vector<uint32_t> body_quad_uvs;
    std::vector<float> uvs;           // 2 per texture coordinate
};
BaseMesh read_base_mesh(const std::string& obj_path);

// A sparse morph: xyz += weight * delta at the listed vertices.
struct Target {
    std::vector<uint32_t> vertices;
    std::vector<float> deltas;  // 3 per entry, metres
    std::size_t size() const { return vertices.size(); }
};
Target read_target(const std::string& path);

// The macro sliders, each in [0, 1] (ethnic values sum to 1).
struct MacroSliders {
    double gender = 0.5, age = 0.5, muscle = 0.5, weight = 0.5, height = 0.5, proportions = 0.5;
    double african = 1.0 / 3, asian = 1.0 / 3, caucasian = 1.0 / 3;
    double breast_size = 0.5, breast_firmness = 0.5;
};

// Age in years <-> slider (the asset's piecewise-linear rule).
double age_years(double slider);
double age_slider(double years);

// A macro target: its weight is the product of its tokens' values for the current sliders.
struct MacroTarget {
    std::string name;                 // path below targets/, e.g. "macrodetails/height/female-..."
    std::vector<std::string> tokens;  // the known tokens of its file name
    Target target;
};
double macro_weight(const std::vector<std::string>& tokens, const MacroSliders& s);

// A body-shape modifier slider: two-sided (value in [-1, 1]; decr side weighted by max(0, -v),
// incr side by max(0, v)) or one-sided (value in [0, 1]).
struct Modifier {
    std::string name;    // e.g. "measure/measure-waist-circ"
    int decr = -1;       // index into Assets::modifier_targets, or -1
    int incr = -1;
};

struct Bone {
    std::string name, parent;        // parent "" for the root
    std::string head, tail;          // joint names
    double roll = 0;                 // radians about the head->tail axis (game-engine rig)
    std::vector<std::string> reference, weights_reference;  // default-rig bones it stands for
};
struct Rig {
    std::vector<Bone> bones;                                   // file order
    std::map<std::string, std::vector<uint32_t>> joints;       // joint name -> vertices (mean = position)
};
Rig read_rig(const std::string& mhskel_path);

// {bone: [(vertex, weight)]} of the default rig.
using RigWeights = std::map<std::string, std::vector<std::pair<uint32_t, float>>>;
RigWeights read_rig_weights(const std::string& mhw_path);

struct Assets {
    std::string root;
    BaseMesh base;
    std::vector<MacroTarget> macro_targets;
    std::vector<Target> modifier_targets;
    std::vector<Modifier> modifiers;  // body-shape modifiers only (see assets.cpp)
    Rig default_rig, game_rig;
    RigWeights default_weights;
    std::string manifest;             // the first lines of MANIFEST.sha256 (source commits)
};

// Loads everything from the shared/makehuman folder; throws ssc::Error(SSC_ERROR_IO) when a file is
// missing or malformed.
Assets load_assets(const std::string& root);

// Appends the body-shape modifiers of the named groups of a modifier file of the assets
// (data/modifiers/FILE, e.g. "modeling_modifiers.json" and {"neck", "armslegs"}) to a.modifiers:
// what training leaves out, for bodies the trained model cannot represent. Throws like load_assets.
void add_modifier_groups(Assets& a, const std::string& file, const std::vector<std::string>& groups);

// A body: base + sum of weighted macro targets + modifier targets. modifier_values: one value
// per Assets::modifiers entry (empty = all zero). xyz receives all vertices, metres.
void generate_body(const Assets& a, const MacroSliders& s, const std::vector<double>& modifier_values, std::vector<float>& xyz);

}  // namespace ssc::training::mh
