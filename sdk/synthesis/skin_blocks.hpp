// The skinning of a mesh in its own vertex order, 16 consecutive vertices at a time: each block of
// 16 lists the joints that move any of its vertices (the union of their influences, 2.9 joints on
// average for the default model) with 16 weights per joint, 0 and masked off in the lanes the
// joint does not move. A block's positions are then loaded and stored whole, in and out of the
// caller's arrays, with no gathers, scatters or second copy in another order (docs/speed.md,
// "Skinning in vertex order by joint unions").
//
// Bits: each lane blends its own joints in the order SkinLayout gives them (by joint index), w_0 M_0
// first and then fused multiply-adds, the other joints' entries masked off, so a vertex gets the
// same bits as SkinLayout's skinning on every path.
#pragma once

#include "common/alloc.hpp"

#include <cstdint>

namespace ssc {

struct SkinBlocks {
    static constexpr uint32_t kLanes = 16;
    uint32_t vertex_count = 0;
    Vec<uint32_t> first;     // per block, and one past the last: its entries [first[b], first[b + 1])
    Vec<uint8_t> unit;       // per block: one joint of weight 1 in all 16 lanes (then w M = M exactly)
    Vec<uint32_t> offsets;   // per entry: joint * 16, where the joint's skinning matrix starts
    Vec<uint16_t> lanes;     // per entry: the lanes it moves (bit l: vertex 16 b + l)
    Vec<float> weights;      // per entry, 16 lanes (0 where its bit is clear)

    uint32_t block_count() const { return (vertex_count + kLanes - 1) / kLanes; }
};

// The blocks of V vertices with 4 joints and 4 weights each (weights <= 0: unused). A vertex that
// names a joint twice gets two entries for it, as SkinLayout blends it twice.
SkinBlocks build_skin_blocks(uint32_t V, const uint16_t* joints, const float* weights, const Allocator* alloc);

}  // namespace ssc
