// A contact sheet of bodies: each body's front and side views side by side, at one common scale,
// a few bodies a row, each with an optional caption. `sscape synth --png` and the benchmarks'
// pictures of poses use it.
#pragma once

#include <string>
#include <vector>

namespace ssc::render {

// bodies: packed xyz per body (the same triangles); captions: empty, or one per body. Throws
// ssc::Error (IO) when the file cannot be written.
void write_body_sheet(const std::string& path, const std::vector<std::vector<float>>& bodies, const std::vector<uint32_t>& triangles,
                      const std::vector<std::string>& captions = {}, int per_row = 5);

}  // namespace ssc::render
