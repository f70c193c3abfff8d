// A picture of a body's landmarks: the body from the front, the back and the side, then the head
// close up from the front and the side, each visible landmark a red dot.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ssc::render {

// xyz: the body's vertices (packed), tris: its triangles, landmarks: their positions (packed xyz).
// Throws ssc::Error on I/O.
void write_landmark_picture(const std::string& path, const std::vector<float>& xyz, const std::vector<uint32_t>& tris,
                            const std::vector<float>& landmarks);

}  // namespace ssc::render
