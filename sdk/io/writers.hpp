// Writers for measurement files (the simulator's output): CAESAR .lnd landmark files and 16-bit
// PGM depth images.
#pragma once

#include "io/readers.hpp"

namespace ssc::io {

// Writes landmarks as a CAESAR .lnd file (millimetres; the header keys of ../shared/docs/landmarks.md).
// Temporary file + rename: no partial file on failure. Throws ssc::Error(SSC_ERROR_IO).
void write_lnd(const std::string& path, const std::string& subject, const std::vector<LandmarkRecord>& landmarks);

// Writes a depth image as a binary 16-bit PGM in millimetres (rounded; 0 = no reading; depths
// beyond 65.535 m are written as 0), with the camera as "# sscape" header comments when
// has_intrinsics / has_pose are set (read_pgm_depth reads them back). Temporary file + rename.
// Throws ssc::Error(SSC_ERROR_IO).
void write_pgm_depth(const std::string& path, const DepthImage& image);

}  // namespace ssc::io
