// Levels of detail for a trained model (issue 49; the format's DetailLevel): MakeHuman's proxy
// meshes and a simplification of the template, each vertex bound to the body's vertices once, on
// the template, by fixed weights that then hold for every shape.
#pragma once

#include "makehuman/assets.hpp"
#include "sscape_format/model_data.hpp"

#include <string>
#include <vector>

namespace ssc::training {

struct LevelSpec {
    // The proxies of makehuman-assets/base/proxymeshes to bind, by name, finest first after the
    // simplified level.
    std::vector<std::string> proxies = {"female1605", "proxy741"};
    // The simplified level's vertex count (about; 0: none): meshoptimizer's quadric simplifier on
    // the template, UV seams kept.
    uint32_t simplified_vertices = 4000;
};

// What each level is and how closely it follows the body (metres, on the template).
struct LevelReport {
    std::string name;
    uint32_t vertices = 0, triangles = 0;
    double offset_mean = 0, offset_max = 0;  // how far the level's vertices lie off the body's surface
};

// The levels of model m (its mesh, skin and landmarks set), bound on `body`: all of the base
// mesh's vertices of one body (helpers included, metres; generate_body's output), whose first
// m.vertex_count() are the model's. Finest first: the simplified level, then the proxies.
std::vector<format::DetailLevel> make_detail_levels(const mh::Assets& assets, const format::ModelData& m, const std::vector<float>& body,
                                                    const LevelSpec& spec, std::vector<LevelReport>* report = nullptr);

}  // namespace ssc::training
