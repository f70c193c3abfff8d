// Coding of the quantized shape basis inside the file. Each quantized value is predicted from the
// same component's value at a neighbouring vertex (a breadth-first spanning tree of the mesh), and
// only the residuals are stored, as 4 byte planes of zigzag-coded 32-bit integers. The basis is
// spatially smooth, so residuals are small and the planes compress well under zstd.
#pragma once

#include "model_data.hpp"

#include <cstdint>
#include <vector>

namespace ssc::format {

struct PredictionTree {
    std::vector<uint32_t> order;      // vertex coded at each position
    std::vector<uint32_t> predictor;  // per position: the position predicting it (itself for roots)
};

// Breadth-first spanning forest over the edges of the triangles and quads.
PredictionTree build_prediction_tree(uint32_t vertex_count, const Vec<uint32_t>& triangles, const Vec<uint32_t>& quads);

std::vector<uint8_t> encode_residuals(const QuantizedBasis& b, uint32_t vertex_count, const PredictionTree& tree);

// Inverse of encode_residuals. The tree and plane sizes are checked here (untrusted input);
// q is resized to components * 3 * vertex_count.
void decode_residuals(const uint8_t* planes, std::size_t plane_bytes, uint32_t vertex_count, uint32_t components,
                      const uint32_t* order, const uint32_t* predictor, Vec<int16_t>& q);

}  // namespace ssc::format
