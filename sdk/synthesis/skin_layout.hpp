// The skinning layout of a mesh (the body's, or a level of detail's): vertices sorted by the set of
// joints that influence them, each run of vertices sharing a set padded to whole blocks of 8
// (repeating its last vertex, which rewrites the same value). Within a run the joints' matrices are
// constants, so 8 vertices are skinned at once from structure-of-arrays weights; a block of 8
// consecutive vertex indices loads and stores positions directly, any other block gathers and
// scatters. Built once at load (Model) and read by kernels::skin_slots.
//
// Positions may also be kept in slot order (a block of slot_count() per coordinate, slot s at s):
// then every block is read and written whole, which is how a body skins its full mesh
// (kernels::skin_slots_in_slot_order); first_slot maps the result back to vertex order.
#pragma once

#include "common/alloc.hpp"

#include <cstdint>
#include <vector>

namespace ssc {

struct SkinLayout {
    static constexpr uint32_t kBlock = 8;
    struct Run {
        uint32_t begin, end;     // slots in the arrays below, multiples of kBlock
        uint32_t influences;     // 1..4
        uint32_t offsets[4];     // joint * 16: where each joint's skinning matrix starts
    };
    uint32_t vertex_count = 0;   // the mesh's vertices (the planar blocks' length)
    std::vector<Run> runs;
    Vec<uint32_t> vertices;      // per slot
    Vec<float> weights[4];       // per slot, influence i
    Vec<uint8_t> contiguous;     // per block
    Vec<uint32_t> first_slot;    // per vertex: the first slot holding it

    uint32_t slot_count() const { return runs.empty() ? 0 : runs.back().end; }
};

// The layout of V vertices with 4 joints and 4 weights each (weights <= 0: unused).
SkinLayout build_skin_layout(uint32_t V, const uint16_t* joints, const float* weights, const Allocator* alloc);

}  // namespace ssc
