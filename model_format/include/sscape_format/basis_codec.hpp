// Coding of the quantized shape basis inside the file. Each quantized value is predicted from the
// same component's value at a neighbouring vertex (a breadth-first spanning tree of the mesh), and
// only the residuals are stored, as 4 byte planes of zigzag-coded 32-bit integers. The basis is
// spatially smooth, so residuals are small and the planes compress well under zstd.
//
// Mirror prediction (container 2.0): bodies are nearly left-right symmetric, so a vertex with a
// mirror twin coded earlier is predicted from the twin, and only the asymmetry is coded, itself
// predicted from the tree parent's: pred = S q(twin) + q(parent) - S q(twin of parent), with S per
// component and axis the symmetry's sign (component sign s_k = +1 symmetric, -1 antisymmetric, 0
// none; the x axis flips: S = s_k * (-1, 1, 1)). Halves the default model's basis (docs: model_format/README.md).
#pragma once

#include "model_data.hpp"

#include <cstdint>
#include <vector>

namespace ssc::format {

struct PredictionTree {
    std::vector<uint32_t> order;      // vertex coded at each position
    std::vector<uint32_t> predictor;  // per position: the position predicting it (itself for roots)
    std::vector<uint32_t> mirror;     // per position: its mirror twin's position (< it), or itself; empty: no mirror prediction
};

// Breadth-first spanning forest over the edges of the triangles and quads.
PredictionTree build_prediction_tree(uint32_t vertex_count, const Vec<uint32_t>& triangles, const Vec<uint32_t>& quads);

// The same over one side and the centre (x >= 0 and every vertex without a twin), then each twin
// on the other side right after, in its twin's order, with the mirror of its twin's parent as its
// parent. Twins: vertex pairs mirrored across x = 0 within `tolerance` (metres) in positions
// (xyz per vertex), each the other's nearest mirror image.
PredictionTree build_mirror_tree(uint32_t vertex_count, const Vec<uint32_t>& triangles, const Vec<uint32_t>& quads,
                                 const float* positions, double tolerance);

struct EncodedBasis {
    std::vector<uint8_t> planes;
    std::vector<int8_t> signs;  // per component with a mirror tree (the cheaper of +1, -1, 0); empty without
};
EncodedBasis encode_basis(const QuantizedBasis& b, uint32_t vertex_count, const PredictionTree& tree);

// Inverse of encode_basis. The tree, the mirror arrays (null: none) and the plane sizes are checked
// here (untrusted input); q is resized to components * 3 * vertex_count.
void decode_residuals(const uint8_t* planes, std::size_t plane_bytes, uint32_t vertex_count, uint32_t components,
                      const uint32_t* order, const uint32_t* predictor, const uint32_t* mirror, const int8_t* signs,
                      Vec<int16_t>& q);

}  // namespace ssc::format
