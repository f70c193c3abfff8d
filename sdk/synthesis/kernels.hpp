// The synthesis stages as plain functions over arrays, shared by single bodies and batches so both
// compute bit-identical results:
//   shape    coefficients -> rest vertices (planar) and rest joints      (only when the shape changes)
//   skeleton rest joints + pose -> joint world, inverse bind, skinning matrices
//   skin     rest vertices + skinning matrices -> posed vertices (linear blend skinning)
//   normals, landmarks: from posed vertices
#pragma once

#include "cpu.hpp"
#include "skin_blocks.hpp"
#include "skin_layout.hpp"
#include "sscape_format/model_data.hpp"

#include <cstddef>
#include <cstdint>

namespace ssc {
class Model;

namespace kernels {

// scaled[k] = coeffs[k] (standard deviations) * step[k] (metres per quantization unit): the
// per-component factors shape() applies to the 16-bit basis. K values each.
void scale_coefficients(const Model& m, const float* coeffs, float* scaled);

// For bodies g < count: rest[g] (Model::padded_rows() floats, planar: x block, y block, z block,
// then padding) = mean + basis * coeffs[g]
// and joints[g] (3J) likewise, from scale_coefficients() output. Bodies share passes over the
// basis, so larger counts amortise its memory traffic; results do not depend on count.
void shape(const Model& m, std::size_t count, const float* const* scaled, float* const* rest, float* const* joints);
// shape() in parts, for splitting one call over threads with the same results: the rest rows of
// panels [first_panel, end_panel) (Model::kChunk rows each; padded_rows() / kChunk in all), and the
// joints.
void shape_rows(const Model& m, std::size_t count, const float* const* scaled, float* const* rest, std::size_t first_panel,
                std::size_t end_panel);
// The same with the kernel's instruction set chosen by the caller (lowered to what the CPU
// supports): tests compare the paths; the results are the same bits.
void shape_rows(const Model& m, std::size_t count, const float* const* scaled, float* const* rest, std::size_t first_panel,
                std::size_t end_panel, Isa isa);
void shape_joints(const Model& m, std::size_t count, const float* const* scaled, float* const* joints);

// A skinning matrix: column-major 4x4 (last row 0 0 0 1), aligned for SIMD loads.
struct SkinMatrix {
    alignas(32) float m[16];
};

// Floats per joint of skeleton_rest()'s frames, of skeleton_pose()'s scratch and of skeleton()'s.
inline constexpr std::size_t kSkeletonRest = 27, kSkeletonPoseScratch = 12, kSkeletonScratch = kSkeletonRest + kSkeletonPoseScratch;

// quats: 4J unit quaternions xyzw (pose, in each joint's rest frame); translation: 3 floats;
// scratch: kSkeletonScratch * J floats. Outputs (any may be null): world and inverse bind as
// column-major 4x4, skinning matrices. Allocates nothing.
void skeleton(const Model& m, const float* joints_rest, const float* quats, const float* translation, float* scratch,
              float* world16, float* inverse_bind16, SkinMatrix* skinning);
// skeleton() in its two halves, with the same bits: what depends on the shape only (rest_frames,
// kSkeletonRest * J floats, and the inverse bind), once per shape; then each pose (scratch:
// kSkeletonPoseScratch * J floats).
void skeleton_rest(const Model& m, const float* joints_rest, float* rest_frames, float* inverse_bind16);
void skeleton_pose(const Model& m, const float* rest_frames, const float* quats, const float* translation, float* scratch, float* world16,
                   SkinMatrix* skinning);

// Posed vertex v = sum_i w_i * skinning[j_i] * rest(v). rest and out are planar (x block, y block,
// z block; 3V floats, out must not alias rest).
void skin(const Model& m, const float* rest_planar, const SkinMatrix* skinning, float* out_planar);
// skin() for the skinning layout's slots [first, end) (Model::skin_runs; multiples of
// Model::kSkinBlock) of skin_slot_count(m): disjoint ranges write disjoint vertices, so threads
// may each take one, with the same results.
uint32_t skin_slot_count(const Model& m);
void skin_slots(const Model& m, const float* rest_planar, const SkinMatrix* skinning, float* out_planar, uint32_t first, uint32_t end);
void skin_slots(const Model& m, const float* rest_planar, const SkinMatrix* skinning, float* out_planar, uint32_t first, uint32_t end,
                Isa isa);  // as shape_rows with an Isa
// The same for any mesh's layout (a level of detail's: Model::level_skin), planar over its vertices.
void skin_slots(const SkinLayout& layout, const float* rest_planar, const SkinMatrix* skinning, float* out_planar, uint32_t first,
                uint32_t end, Isa isa);

// Skinning in vertex order by blocks of 16 vertices (skin_blocks.hpp), blocks [first, end):
// rest planar over s.vertex_count; the posed positions planar into out_planar and interleaved into
// xyz (vertex v at xyz + 3 v), each unless null. The same bits as skin_slots. Disjoint block ranges
// write disjoint vertices.
void skin_blocks(const SkinBlocks& s, const float* rest_planar, const SkinMatrix* skinning, float* out_planar, float* xyz, uint32_t first,
                 uint32_t end, Isa isa);
// Whether skin_blocks beats the skin layout's runs on this instruction set: on AVX-512 only (AVX2
// has no masked multiply-add; elsewhere skin_blocks runs one vertex at a time; docs/speed.md).
// kernels::skin and Body choose by it.
inline bool skin_by_blocks(Isa isa) { return isa == Isa::Avx512; }
// Skinning with positions in the layout's slot order (skin_layout.hpp): rest_slots and out_slots
// hold an x, a y and a z block of layout.slot_count() floats, slot s holding vertex
// layout.vertices[s]. The same bits as skin_slots, with every block read and written whole.
void skin_slots_in_slot_order(const SkinLayout& layout, const float* rest_slots, const SkinMatrix* skinning, float* out_slots, uint32_t first,
                              uint32_t end, Isa isa);
// Planar vertex order (blocks of layout.vertex_count) to slot order, slots [first, end).
void to_slot_order(const SkinLayout& layout, const float* planar, float* slots, uint32_t first, uint32_t end);
// Slot order back to planar vertex order, vertices [first, end).
void from_slot_order(const SkinLayout& layout, const float* slots, float* planar, uint32_t first, uint32_t end);
// Slot order to xyz at stride bytes (vertex v at out + v * stride), vertices [first, end).
void slots_to_xyz(const SkinLayout& layout, const float* slots, float* out, std::size_t stride, uint32_t first, uint32_t end);

// Area-weighted unit normals of the mesh with planar vertices into out (packed xyz).
// scratch: 3 floats per triangle. Allocates nothing.
void normals(const Model& m, const float* planar, float* scratch, float* out);
// normals() in two steps, for splitting over threads with the same results: the face normals
// (scratch above) of triangles [first, end), then, once all are written, the unit normals of
// vertices [first, end).
void face_normals(const Model& m, const float* planar, float* face, uint32_t first, uint32_t end);
void vertex_normals(const Model& m, const float* face, float* out, uint32_t first, uint32_t end);

// Landmark positions from planar vertices (x block, y block, z block), xyz at stride bytes.
void landmarks(const format::ModelData& d, const float* planar, float* out, std::size_t stride);

// Planar (x block, y block, z block) to xyz at stride bytes. streaming: bypass the cache for
// outputs too large to stay in it (batches).
void planar_to_xyz(const float* planar, uint32_t n, float* out, std::size_t stride, bool streaming = false);

}  // namespace kernels
}  // namespace ssc
