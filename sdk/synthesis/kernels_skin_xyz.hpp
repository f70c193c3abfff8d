// Skinning that also writes the caller's interleaved xyz (12 bytes a vertex) as each block is
// posed: what Body::posed_xyz uses when the vertices are asked for before anything else of the
// pose, saving the separate pass from planar or slot order to xyz (docs/speed.md).
#pragma once

#include "kernels.hpp"

namespace ssc::kernels {

// skin_slots_in_slot_order over slots [first, end), out_slots written as it writes them, and
// besides each of those slots' vertices v at xyz + 3 v: the same bits as slots_to_xyz of the
// result, block by block while it is still in registers. (Vertex order has no such variant: its
// gathered blocks already cost more than planar_to_xyz does afterwards.)
void skin_slots_and_xyz(const SkinLayout& layout, const float* rest_slots, const SkinMatrix* skinning, float* out_slots, float* xyz,
                        uint32_t first, uint32_t end, Isa isa);

}  // namespace ssc::kernels
