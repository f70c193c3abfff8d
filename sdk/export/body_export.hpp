// A body written to a file as people and tools want it: the posed mesh (OBJ with UVs and normals,
// binary PLY) or the rigged body (binary glTF: bind pose, skeleton posed by the body's joints,
// skin). The C API's ssc_body_write_file and the command line's outputs come through here.
#pragma once

#include "synthesis/body.hpp"

#include <string>

namespace ssc::exporters {

enum class BodyFormat { Obj, Ply, Glb };

// The format a path names by its extension (.obj, .ply, .glb; any case); throws
// SSC_ERROR_INVALID_ARGUMENT naming the formats for anything else.
BodyFormat format_of(const std::string& path);

// Writes the body (its current shape and pose) to path; the file appears whole or not at all.
// Throws ssc::Error: SSC_ERROR_IO when the file cannot be written.
void write_body(Body& body, const std::string& path, BodyFormat format);

}  // namespace ssc::exporters
