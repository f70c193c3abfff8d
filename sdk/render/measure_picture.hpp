// A picture of where a body's measurements are taken: the body from the front, the side and the
// back with each measurement's path (tape loops, lengths) drawn where it is visible.
#pragma once

#include "measure/measurements.hpp"

#include <string>
#include <vector>

namespace ssc::render {

// xyz: the body's rest-pose vertices (packed); paths: Measurer::measure's. Throws ssc::Error on I/O.
void write_measurement_picture(const std::string& path, const std::vector<float>& xyz, const std::vector<uint32_t>& triangles,
                               const std::vector<measure::Path>& paths);

}  // namespace ssc::render
