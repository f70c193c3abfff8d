// The synthesis stages as plain functions over arrays, shared by single bodies and batches so both
// compute bit-identical results:
//   shape    coefficients -> rest vertices (planar) and rest joints      (only when the shape changes)
//   skeleton rest joints + pose -> joint world, inverse bind, skinning matrices
//   skin     rest vertices + skinning matrices -> posed vertices (linear blend skinning)
//   normals, landmarks: from posed vertices
#pragma once

#include "sscape_format/model_data.hpp"

#include <cstddef>
#include <cstdint>

namespace ssc {
class Model;

namespace kernels {

// For bodies g < count: rest[g] (3V planar: x block, y block, z block) = mean + basis * coeffs[g]
// and joints[g] (3J) likewise; coeffs[g] holds K values in standard deviations. The basis is read
// once per row block for all bodies, so larger counts amortise its memory traffic.
void shape(const Model& m, std::size_t count, const float* const* coeffs, float* const* rest, float* const* joints);

// A 3x4 row-major affine transform: what skinning blends.
struct Affine34 {
    float m[12];
};

// Floats of scratch that skeleton() needs per joint.
inline constexpr std::size_t kSkeletonScratch = 21;

// quats: 4J unit quaternions xyzw (pose, in each joint's rest frame); translation: 3 floats;
// scratch: kSkeletonScratch * J floats. Outputs (any may be null): world and inverse bind as
// column-major 4x4, skinning as Affine34. Allocates nothing.
void skeleton(const Model& m, const float* joints_rest, const float* quats, const float* translation, float* scratch,
              float* world16, float* inverse_bind16, Affine34* skinning);

// Posed vertex v = sum_i w_i * skinning[j_i] * rest(v); out is xyz at stride bytes.
void skin(const Model& m, const float* rest_planar, const Affine34* skinning, float* out, std::size_t stride);

// Area-weighted unit normals of a mesh given as xyz at in_stride bytes. out is used to accumulate:
// it must not alias xyz. Allocates nothing.
void normals(const Model& m, const float* xyz, std::size_t in_stride, float* out, std::size_t out_stride);

// Landmark positions from packed xyz vertices.
void landmarks(const format::ModelData& d, const float* xyz, float* out, std::size_t stride);

// Planar (x block, y block, z block) to xyz at stride bytes.
void planar_to_xyz(const float* planar, uint32_t n, float* out, std::size_t stride);

}  // namespace kernels
}  // namespace ssc
