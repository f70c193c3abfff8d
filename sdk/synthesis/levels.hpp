// Levels of detail at run time (the file's DetailLevel, issue 49): a level's rest vertices are its
// fixed affine map of the body's (exact for every shape); posed by the level's own skin of at most
// 4 influences, as an engine poses it, so pose-only synthesis costs in proportion to the level's
// vertices. Triangles around each vertex are derived once at load for the normals.
#pragma once

#include "kernels.hpp"
#include "sscape_format/model_data.hpp"

#include <cstdint>
#include <vector>

namespace ssc {

// What synthesis derives from one level: the triangles around each vertex (CSR, N + 1 offsets).
struct LevelTopology {
    std::vector<uint32_t> vertex_triangle_offsets, vertex_triangles;
    explicit LevelTopology(const format::DetailLevel& level);
};

namespace levels {

// The level's vertices, planar (x block, y block, z block of N floats), from the body's in planar
// layout (blocks of V floats). Posing is kernels::skin_slots with the level's SkinLayout.
void from_body(const format::DetailLevel& level, const float* body_planar, uint32_t V, float* out_planar);

// Area-weighted unit vertex normals (xyz) of planar vertices; face_scratch: 3 floats per triangle.
void normals(const format::DetailLevel& level, const LevelTopology& topology, const float* planar, float* face_scratch, float* out_xyz);

}  // namespace levels
}  // namespace ssc
