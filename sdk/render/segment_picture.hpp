// A picture of a model's segment shape spaces: the mean body coloured by segment (blended in the
// bands), then each segment's first component at -3 and +3 standard deviations.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ssc::render {

struct SegmentView {
    std::string name;
    std::vector<float> weight;       // per body vertex: how much of it belongs to the segment
    std::vector<float> minus, plus;  // the body (packed xyz) with the segment's first component at -3 / +3 SD
};

// mean: the mean body (packed xyz), tris: its triangles. Throws ssc::Error on I/O.
void write_segment_picture(const std::string& path, const std::vector<float>& mean, const std::vector<uint32_t>& tris,
                           const std::vector<SegmentView>& segments);

}  // namespace ssc::render
