// Writers for measurement files (the simulator's output): CAESAR .lnd landmark files.
#pragma once

#include "io/readers.hpp"

namespace ssc::io {

// Writes landmarks as a CAESAR .lnd file (millimetres; the header keys of ../shared/docs/landmarks.md).
// Temporary file + rename: no partial file on failure. Throws ssc::Error(SSC_ERROR_IO).
void write_lnd(const std::string& path, const std::string& subject, const std::vector<LandmarkRecord>& landmarks);

}  // namespace ssc::io
