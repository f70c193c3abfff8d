// Outputs never replace inputs: the check every tool that writes files makes before any work.
#pragma once

#include "common/error.hpp"

#include <string>
#include <vector>

namespace ssc {

// Throws ssc::Error(SSC_ERROR_INVALID_ARGUMENT) when `output` names the file of one of `inputs`: the
// same path, another spelling of it, or a symbolic or hard link to it. A tool never replaces what it
// reads (`register scan.ply -o scan.ply` once replaced the raw scan). Empty names are skipped; an
// output that does not exist yet is no input.
void refuse_output_over_input(const std::string& output, const std::vector<std::string>& inputs);

}  // namespace ssc
