// Segment shape spaces at run time (see the format's ShapeSegment): each segment's basis decoded
// once and regressed to the joints, so that a body adds one column per non-zero coefficient to its
// rest vertices and joints.
#pragma once

#include "common/alloc.hpp"
#include "sscape_format/model_data.hpp"

#include <string>
#include <vector>

namespace ssc {

struct SegmentSpace {
    std::string name;
    uint32_t components = 0;
    uint32_t first = 0;               // where its coefficients start in a body's segment coefficients
    std::vector<uint32_t> vertices;   // the body vertices it moves, sorted
    std::vector<float> weights;       // their blend weights
    Vec<float> basis;                 // [k][axis][i]: metres per standard deviation (blending included)
    Vec<float> joint_basis;           // [k][j][axis]: the same, regressed to the joints
};

std::vector<SegmentSpace> build_segment_spaces(const format::ModelData& data, const Allocator* alloc);

// Adds the segments' shapes to a body's planar rest vertices (x block, y block, z block; V rows
// each) and its joints (xyz per joint). coefficients: every segment's, in segment order.
void add_segment_shapes(const std::vector<SegmentSpace>& segments, uint32_t vertex_count, uint32_t joint_count,
                        const float* coefficients, float* rest_planar, float* joints);

}  // namespace ssc
